"""The safety run's plot, as PNG (``bag_to_csv``): per supervised robot, ``ssm_<robot>.png``
with the separation and S_p (m, left axis) and the speed scale (right axis) over time, from
ssm_supervisor's ``/ssm_supervisor/<robot>/separation``, ``protective_separation`` and
``scale`` (std_msgs/Float64; time is the bag's, simulated time under /use_sim_time, in seconds
from the robot's first sample)."""
import os
import re
from typing import List

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from epuck_vrep_compat.compat.topics import SSM_TOPIC_FORMAT

SERIES = (("separation", "separation"), ("protective_separation", "S_p"), ("scale", "scale"))


def _series(bag, topic):
    times, values = [], []
    for _, msg, t in bag.read_messages(topics=[topic]):
        times.append(t.to_sec())
        values.append(msg.data)
    return np.array(times, dtype=float), np.array(values, dtype=float)


def supervised_robots(topics) -> List[str]:
    pattern = re.compile("^" + re.escape(SSM_TOPIC_FORMAT).replace(r"\{robot\}", "([^/]+)")
                         .replace(r"\{what\}", "separation") + "$")
    return sorted({m.group(1) for m in (pattern.match(t) for t in topics) if m})


def plot_robot(bag, robot: str, path: str) -> str:
    data = {key: _series(bag, SSM_TOPIC_FORMAT.format(robot=robot, what=key))
            for key, _ in SERIES}
    start = min(t[0] for t, _ in data.values() if len(t))
    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    for key, label in SERIES[:2]:
        t, v = data[key]
        ax.plot(t - start, v, label=label + " [m]")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("distance [m]")
    ax.grid(True)
    right = ax.twinx()
    t, v = data["scale"]
    right.plot(t - start, v, color="tab:red", label="speed scale")
    right.set_ylim(-0.05, 1.05)
    right.set_ylabel("speed scale")
    lines = ax.get_legend_handles_labels()[0] + right.get_legend_handles_labels()[0]
    fig.legend(lines, [line.get_label() for line in lines], loc="lower center", ncol=3)
    fig.subplots_adjust(bottom=0.22)
    ax.set_title(f"{robot}: speed and separation monitoring")
    FigureCanvasAgg(fig)
    fig.savefig(path, dpi=100)
    return path


def plot_ssm(bag, topics, outdir: str) -> List[str]:
    """One plot per robot whose separation the bag holds; report lines as plot_all's."""
    return [plot_robot(bag, robot, os.path.join(outdir, f"ssm_{robot}.png"))
            for robot in supervised_robots(topics)]

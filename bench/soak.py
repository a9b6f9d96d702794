#!/usr/bin/python3
"""Soak: does the simulator's memory, thread count or pace drift over a long run?

Two scenarios, one after the other, each for ``--seconds`` (default 3600; ``--minutes 5`` for a
quick look), each in a ROS world of its own (a master on a free port):

* ``swarm``: 100 e-pucks (``epucks.launch``, real time, the swarm benchmark's arena), one
  separate C++ process (``build/subscribe_all``) subscribed to every topic there is;
* ``cell``: the MERLIN cell with the operator's walk, the thesis's nodes, ``operator_tracker``
  and ``ssm_supervisor`` (``merlin_safety.launch nodes:=true``), the same subscriber.

Every ``--period-s`` (10 s) it samples the simulator process (``/vrep``): resident memory
(VmRSS), threads, open descriptors, the real-time factor over the interval (``/clock`` time
over wall time) and the messages the subscriber received in it. Writes ``DIR/soak_<scenario>.csv``
and ``DIR/soak_<scenario>.png``, and prints per scenario the growth after the first minute in %
per hour (a least-squares line through the samples after it, over the value at one minute) of
RSS, threads and descriptors, and the RTF's mean and standard deviation after it. The goal
(issue 27): RSS and threads flat (under 5 % per hour), RTF steady.
Needs a built, sourced workspace and ``bench/build.sh``; use an otherwise idle machine.

    bench/soak.py --out results/soak              # an hour each
    bench/soak.py --minutes 5 --out /tmp/soak     # a quick look
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import threading
import time
import xmlrpc.client

from fuzz_memory import process_figures      # bench/: the same /proc reading

FIELDS = ["wall_s", "sim_s", "rtf", "rss_mb", "threads", "descriptors", "messages",
          "messages_per_s"]
WARM_UP_S = 60.0     # growth is measured after the first minute
HERE = os.path.dirname(os.path.abspath(__file__))


def launch_command(scenario, world):
    if scenario == "swarm":
        return ["roslaunch", "epuck_vrep_compat", "epucks.launch", "n:=100", f"world:={world}"]
    return ["roslaunch", "epuck_vrep_compat", "merlin_safety.launch", "nodes:=true"]


class ProgressReader:
    """The subscriber's progress lines (stderr), the last message count kept."""

    def __init__(self, stream):
        self.messages = 0
        threading.Thread(target=self._read, args=(stream,), daemon=True).start()

    def _read(self, stream):
        for line in stream:
            try:
                self.messages = json.loads(line).get("messages", self.messages)
            except ValueError:
                pass


def sample(scenario, pid, clock, progress, seconds, period_s, path):
    """Every ``period_s`` for ``seconds``: a row of the simulator's figures, written to the CSV
    file at ``path`` as it comes (a run cut short keeps what it had)."""
    rows = []
    started = last_t = time.monotonic()
    last_sim, last_messages = clock.sim_s, 0
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, FIELDS)
        writer.writeheader()
        while time.monotonic() - started < seconds:
            time.sleep(max(0.0, last_t + period_s - time.monotonic()))
            now, sim_s, messages = time.monotonic(), clock.sim_s, progress.messages
            rss_mb, threads, descriptors = process_figures(pid)
            row = {"wall_s": round(now - started, 2), "sim_s": round(sim_s, 3),
                   "rtf": round((sim_s - last_sim) / (now - last_t), 4),
                   "rss_mb": round(rss_mb, 2), "threads": threads,
                   "descriptors": descriptors, "messages": messages,
                   "messages_per_s": round((messages - last_messages) / (now - last_t), 1)}
            writer.writerow(row)
            f.flush()
            rows.append(row)
            print(f"{scenario}: {json.dumps(row)}", flush=True)
            last_t, last_sim, last_messages = now, sim_s, messages
    return rows


def run_scenario(scenario, seconds, period_s, out_dir):
    """One scenario in this process (its own master); writes and returns its rows."""
    import rosgraph
    import rospy
    from run_benchmark import ClockWatch, end_group, free_port, scene_file

    port = free_port()
    os.environ["ROS_MASTER_URI"] = f"http://127.0.0.1:{port}"
    master_proc = subprocess.Popen(["rosmaster", "--core", "-p", str(port)],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    world = scene_file(100, 0.30) if scenario == "swarm" else None
    launch = sub = None
    try:
        master = rosgraph.Master("/soak")
        while not master.is_online():
            time.sleep(0.2)
        rospy.init_node("soak", disable_signals=True)
        clock = ClockWatch()
        launch = subprocess.Popen(launch_command(scenario, world), stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL, start_new_session=True)
        while clock.sim_s == 0.0:
            if launch.poll() is not None:
                raise RuntimeError(f"{scenario}: roslaunch ended with {launch.returncode}")
            time.sleep(0.2)
        pid = xmlrpc.client.ServerProxy(master.lookupNode("/vrep")).getPid("/soak")[2]
        sub = subprocess.Popen([os.path.join(HERE, "build", "subscribe_all"), "--regex",
                                "^/.*", "--progress", str(period_s)],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
        progress = ProgressReader(sub.stderr)
        rows = sample(scenario, pid, clock, progress, seconds, period_s,
                      os.path.join(out_dir, f"soak_{scenario}.csv"))
        return rows
    finally:
        for p in (sub, launch):
            end_group(p, 60.0)
        master_proc.terminate()
        master_proc.wait(timeout=30)
        if world:
            os.unlink(world)


def growth_per_hour(rows, field):
    """% per hour of a least-squares line through the samples after the first minute, over
    its value at one minute; None with fewer than two samples after it."""
    points = [(r["wall_s"], float(r[field])) for r in rows if r["wall_s"] >= WARM_UP_S]
    if len(points) < 2:
        return None
    slope, intercept = statistics.linear_regression(*zip(*points))
    base = intercept + slope * WARM_UP_S
    return 100.0 * slope * 3600.0 / base if base else None


def summarise(scenario, rows):
    after = [float(r["rtf"]) for r in rows if r["wall_s"] >= WARM_UP_S]
    parts = [f"{scenario}: {len(rows)} samples"]
    for field in ("rss_mb", "threads", "descriptors"):
        g = growth_per_hour(rows, field)
        parts.append(f"{field} {rows[0][field]} -> {rows[-1][field]}, growth after 1 min "
                     + ("n/a" if g is None else f"{g:+.2f} %/h"))
    if len(after) >= 2:
        parts.append(f"RTF after 1 min {statistics.mean(after):.3f} ± "
                     f"{statistics.stdev(after):.3f} (mean ± SD)")
    return "; ".join(parts)


def plot(scenario, rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    minutes = [float(r["wall_s"]) / 60.0 for r in rows]
    panels = [("rss_mb", "RSS [MB]"), ("threads", "threads"), ("descriptors", "descriptors"),
              ("rtf", "RTF"), ("messages_per_s", "delivered [msg/s]")]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(8, 11))
    for ax, (field, label) in zip(axes, panels):
        ax.plot(minutes, [float(r[field]) for r in rows], marker=".", linewidth=1)
        ax.set_ylabel(label)
        ax.axvline(WARM_UP_S / 60.0, color="grey", linestyle=":", linewidth=1)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("wall time [min]")
    axes[0].set_title(f"soak: {scenario}")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=3600.0, help="per scenario")
    ap.add_argument("--minutes", type=float, help="per scenario, instead of --seconds")
    ap.add_argument("--period-s", type=float, default=10.0)
    ap.add_argument("--scenarios", nargs="+", choices=["swarm", "cell"],
                    default=["swarm", "cell"])
    ap.add_argument("--out", required=True, help="folder of the CSV files and plots")
    ap.add_argument("--one", choices=["swarm", "cell"], help=argparse.SUPPRESS)
    args = ap.parse_args()
    seconds = args.minutes * 60.0 if args.minutes is not None else args.seconds
    os.makedirs(args.out, exist_ok=True)
    if args.one:                         # a child: one scenario in its own ROS world
        run_scenario(args.one, seconds, args.period_s, args.out)
        return
    summaries = []
    for scenario in args.scenarios:     # each in a process of its own: rospy inits once
        subprocess.run([sys.executable, os.path.abspath(__file__), "--one", scenario,
                        "--seconds", str(seconds), "--period-s", str(args.period_s),
                        "--out", args.out], check=True)
        with open(os.path.join(args.out, f"soak_{scenario}.csv")) as f:
            rows = [dict(r, wall_s=float(r["wall_s"])) for r in csv.DictReader(f)]
        plot(scenario, rows, os.path.join(args.out, f"soak_{scenario}.png"))
        summaries.append(summarise(scenario, rows))
    print("\n".join(summaries))


if __name__ == "__main__":
    main()

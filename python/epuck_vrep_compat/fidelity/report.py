"""The sim-vs-real report: Markdown tables (the paper's Table 1 statistics for every source,
the fitted noise with its intervals) and PNG figures (Figs. 3-5), matplotlib's Agg canvas.

Sources are ``{label: Series}`` (``bag_data.Series``), e.g. real, sim_fitted, sim_ideal.
"""
import os

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from epuck_vrep_compat.fidelity.stats import SUMMARY_COLUMNS, summary

FIGURE_SIZE_IN = (8.0, 6.0)
FIGURE_DPI = 100                 # 800 x 600 pixels
PLOT_SENSORS = (0, 1, 6, 7)      # the paper's Fig. 4 sensors


def _row(label, values):
    return f"| {label} | " + " | ".join("—" if np.isnan(v) else f"{v:.5f}" for v in values) + " |"


def table1(sources, ir_sources=None):
    """Table 1's layout: per accelerometer axis and per source, then per IR sensor (of
    ``ir_sources`` when given)."""
    head = "| | " + " | ".join(SUMMARY_COLUMNS) + " |\n|" + " --- |" * (len(SUMMARY_COLUMNS) + 1)
    lines = ["### Accelerometer [m/s²]", "", head]
    for axis, name in enumerate("xyz"):
        for label, s in sources.items():
            if s.accel is not None and len(s.accel):
                lines.append(_row(f"{label} {name}", summary(s.accel[:, axis])))
    lines += ["", "### Proximity sensors [m]", "", head]
    for k in range(8):
        for label, s in (ir_sources or sources).items():
            if k in s.ir:
                lines.append(_row(f"{label} proximity{k}", summary(s.ir[k][1])))
    return "\n".join(lines)


def fitted_table(noise):
    """The fitted parameters with their 95 % intervals and sample counts (the file's ``fit``)."""
    fit = noise["fit"]
    lines = ["| parameter | value | 95 % interval | samples |", "| --- | --- | --- | --- |"]
    for name, f in fit.get("ir", {}).items():
        for key in ("probability", "mean_m", "stddev_m"):
            lines.append(_fit_row(f"{name} {key}", f[key], f["samples"] if key == "probability"
                                  else f["errors"]))
    for sensor, unit in (("accel", "m/s²"), ("gyro", "rad/s")):
        if sensor in fit:
            for kind in ("bias", "stddev"):
                for axis, est in zip("xyz", fit[sensor][kind]):
                    lines.append(_fit_row(f"{sensor} {axis} {kind} [{unit}]", est,
                                          fit[sensor]["samples"]))
    if "accel_x_motion_stddev_m_s2" in fit:
        lines.append(f"| accel x stddev written: the sensor's own, less wheel slip's "
                     f"{fit['accel_x_motion_stddev_m_s2']:.6f} [m/s²] | "
                     f"{noise['imu_noise']['accel_stddev_m_s2'][0]:.6f} | | |")
    return "\n".join(lines)


def _fit_row(name, est, n):
    lo, hi = est["ci95"]
    return f"| {name} | {est['value']:.6f} | [{lo:.6f}, {hi:.6f}] | {n} |"


def error_rates(sources):
    lines = ["| source | " + " | ".join(f"p{k}" for k in range(8)) + " |",
             "|" + " --- |" * 9]
    for label, s in sources.items():
        rates = [((s.ir[k][1] < s.ir[k][2] - 1e-6).mean() if k in s.ir and len(s.ir[k][1])
                  else np.nan) for k in range(8)]
        lines.append(_row(label, rates))
    return "\n".join(lines)


def _save(fig, path):
    FigureCanvasAgg(fig).print_png(path)
    return os.path.basename(path)


def plot_accel(sources, path):
    """Fig. 3: the accelerometer's three axes over time, one line per source."""
    fig = Figure(figsize=FIGURE_SIZE_IN, dpi=FIGURE_DPI)
    for axis, name in enumerate("xyz"):
        ax = fig.add_subplot(3, 1, axis + 1)
        for label, s in sources.items():
            if s.accel is not None and len(s.accel):
                ax.plot(s.imu_t, s.accel[:, axis], label=label, linewidth=0.8)
        ax.set_ylabel(f"{name} [m/s²]")
    ax.set_xlabel("time [s]")
    fig.axes[0].legend(loc="upper right", fontsize="small")
    fig.tight_layout()
    return _save(fig, path)


def plot_proximity(sources, path):
    """Fig. 4: the range of sensors 0, 1, 6, 7 over time, one line per source."""
    fig = Figure(figsize=FIGURE_SIZE_IN, dpi=FIGURE_DPI)
    for i, k in enumerate(PLOT_SENSORS):
        ax = fig.add_subplot(2, 2, i + 1)
        for label, s in sources.items():
            if k in s.ir:
                ax.plot(s.ir[k][0], s.ir[k][1], label=label, linewidth=0.8)
        ax.set_title(f"proximity{k}", fontsize="small")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("range [m]")
    fig.axes[0].legend(loc="lower right", fontsize="small")
    fig.tight_layout()
    return _save(fig, path)


def plot_errors(sources, path, sensors=range(8)):
    """Fig. 5: histograms of the IR errors (max range − reading, where not 0), pooled over the
    given sensors, per source."""
    fig = Figure(figsize=FIGURE_SIZE_IN, dpi=FIGURE_DPI)
    ax = fig.add_subplot(1, 1, 1)
    for label, s in sources.items():
        errors = np.concatenate([s.ir[k][2] - s.ir[k][1] for k in sensors if k in s.ir] or
                                [np.empty(0)])
        errors = errors[errors > 1e-6]
        if errors.size:
            ax.hist(errors * 1000.0, bins=30, alpha=0.5, label=f"{label} ({errors.size})")
    ax.set_xlabel("error [mm]")
    ax.set_ylabel("readings")
    ax.legend(loc="upper right", fontsize="small")
    fig.tight_layout()
    return _save(fig, path)

"""The safety benchmark's report (``safety_bench report``): from the rows of
``experiments/safety_ssm.yaml`` (their ``metric.*`` columns from ``metrics_safety``), one line
per monitor x fault: walks, walks in violation and the time, contacts, the true minimum
separation's p0/p5/p50, the reaction's p50/p99 (steps and seconds), productivity and the
tracker's error; the coverage maps when there are; and each monitor's worst walk (the most
contacts, then the longest violation) with the command that replays it.

A monitor is named by the run's ``monitor.*`` parameters (``ssm``, ``ssm reaction_time_s=0.1``),
a fault by ``fault.fault``. Only ok runs count; failed ones are listed apart.
"""
import math
import os

import numpy as np

MONITOR, FAULT = "param.monitor.monitor", "param.fault.fault"
REPLAY = ("ROS_PACKAGE_PATH=experiments/safety_ssm:$ROS_PACKAGE_PATH roslaunch ssm_bench "
          "replay.launch seed:={seed} fault:={fault}{args} rviz:=true")


def monitor_label(row):
    """``ssm``, or ``ssm reaction_time_s=0.1 ...`` when the monitor's parameters were varied."""
    extra = sorted((k[len("param.monitor."):], v) for k, v in row.items()
                   if k.startswith("param.monitor.") and k != MONITOR and not _missing(v))
    return " ".join([str(row.get(MONITOR, "?"))] + [f"{k}={_num(v)}" for k, v in extra])


def _missing(v):
    return v is None or (isinstance(v, float) and math.isnan(v))


def _num(v):
    return f"{v:g}" if isinstance(v, float) else str(v)


def _values(rows, column):
    values = np.array([r.get("metric." + column, math.nan) for r in rows], dtype=float)
    return values[np.isfinite(values)]


def _pct(values, q, fmt="{:.3f}"):
    return fmt.format(float(np.percentile(values, q))) if values.size else "–"


def cell_line(rows):
    """One table line's figures for the ok rows of one monitor x fault."""
    violation = _values(rows, "violation_s")
    sep = _values(rows, "min_separation_m")
    reaction = _values(rows, "reaction_steps")
    return {
        "walks": len(rows),
        "in violation": f"{int(np.count_nonzero(violation > 0))} ({violation.sum():.2f} s)",
        "contacts": f"{int(_values(rows, 'contacts').sum())}",
        "min sep p0/p5/p50 [m]": "/".join(_pct(sep, q, "{:.2f}") for q in (0, 5, 50)),
        "reaction p50/p99 [steps]": "/".join(_pct(reaction, q, "{:.0f}") for q in (50, 99)),
        "reaction p99 [s]": _pct(_values(rows, "reaction_s"), 99, "{:.2f}"),
        "stopped at the end": f"{int(np.count_nonzero(_values(rows, 'final_scale') <= 0.0))}",
        "productivity": _pct(_values(rows, "productivity"), 50, "{:.2f}"),
        "tracker error [m]": _pct(_values(rows, "tracker_error_mean_m"), 50, "{:.3f}"),
    }


def cells(rows):
    """{(monitor, fault): ok rows}, sorted: our supervisor at defaults first."""
    out = {}
    for row in rows:
        if row.get("status") == "ok":
            out.setdefault((monitor_label(row), str(row.get(FAULT, "none"))), []).append(row)
    return dict(sorted(out.items(), key=lambda kv: (kv[0][0] != "ssm", kv[0][0],
                                                    kv[0][1] != "none", kv[0][1])))


def worst_walk(rows):
    """The ok row with the most contacts, then the longest violation, then the smallest true
    separation (which alone says little: the operator walks through a stopped robot)."""
    def badness(r):
        def value(name, default):
            v = r.get("metric." + name, default)
            return v if v is not None and math.isfinite(v) else default
        return (-value("contacts", 0.0), -value("violation_s", 0.0),
                value("min_separation_m", math.inf))
    return min(rows, key=badness) if rows else None


def replay_command(row):
    args = "".join(f" {k[len('param.monitor.'):]}:={_num(v)}" for k, v in sorted(row.items())
                   if k.startswith("param.monitor.") and not _missing(v))
    return REPLAY.format(seed=row["seed"], fault=row.get(FAULT, "none"), args=args)


def markdown(rows, title, maps=(), wall_s=None):
    """The report's text."""
    by_cell = cells(rows)
    lines = [f"# {title}", ""]
    failed = [r for r in rows if r.get("status") != "ok"]
    total = f"{len(rows)} runs ({len(failed)} failed)"
    if wall_s is not None:
        total += f", {wall_s / 60.0:.1f} min of wall time (every invocation's, summed)"
    lines += [total + ".", "",
              "Per walk: the true minimum separation (the simulator's core, not the tracker), "
              "time in violation (below the standard's S_p for the robot's true speed while it "
              "moves), contacts while the robot moves, the reaction from the first step below "
              "S_p to the first reduced scale (negative: reduced before), productivity (the "
              "task's progress against no operator), the tracker's mean error. "
              "See docs/safety_benchmark.md.", ""]
    if by_cell:
        header = ["monitor", "fault"] + list(cell_line(next(iter(by_cell.values()))))
        lines += ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
        for (monitor, fault), chosen in by_cell.items():
            line = cell_line(chosen)
            lines.append("| " + " | ".join([monitor, fault] + [str(v) for v in line.values()])
                         + " |")
        lines.append("")
    lines += ["## Worst walk of each monitor", ""]
    monitors = {}
    for (monitor, _fault), chosen in by_cell.items():
        monitors.setdefault(monitor, []).extend(chosen)
    for monitor, chosen in monitors.items():
        row = worst_walk(chosen)
        lines += [f"- **{monitor}**: seed {row['seed']}, fault {row.get(FAULT, 'none')}: "
                  f"min separation {row.get('metric.min_separation_m', math.nan):.3f} m, "
                  f"violation {row.get('metric.violation_s', math.nan):.2f} s, contacts "
                  f"{row.get('metric.contacts', math.nan):.0f}. Replay:",
                  f"  `{replay_command(row)}`"]
    if maps:
        lines += ["", "## Coverage maps", "",
                  "Per 0.4 m cell of the floor: the tracker's mean error (left) and how many "
                  "ceiling cameras see the operator there (right), as he walks over the whole "
                  "floor (`experiments/safety_ssm/coverage.yaml`).", ""]
        lines += [f"![{os.path.splitext(os.path.basename(m))[0]}]({os.path.basename(m)})"
                  for m in maps]
    if failed:
        lines += ["", "## Failed runs", ""]
        lines += [f"- {r.get('run_key')}: seed {r.get('seed')}, {monitor_label(r)}, "
                  f"{r.get(FAULT)}: {str(r.get('error', ''))[:200]}" for r in failed]
    return "\n".join(lines) + "\n"


def write(out_dir, rows, title="Safety benchmark: speed and separation monitoring",
          maps=(), wall_s=None):
    """Writes ``out_dir/report.md``; returns its path."""
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, "report.md")
    with open(path, "w") as f:
        f.write(markdown(rows, title, maps, wall_s))
    return path

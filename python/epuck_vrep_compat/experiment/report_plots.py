"""The experiment report's figures (PNG, matplotlib's Agg canvas, no pyplot and no global
backend switch): a metric against one varied parameter, with each cell's mean and 95 %
interval, and a metric's per-seed scatter.

A numeric parameter is drawn on an x axis at its values; any other (names, booleans, lists) at
labelled, evenly spaced positions. Summary rows are ``report.summarize``'s.
"""
import os

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

FIGURE_SIZE_IN = (7.0, 4.5)
FIGURE_DPI = 100                 # 700 x 450 pixels
MAX_SERIES = 6                   # more lines than this cannot be told apart
DODGE = 0.25                     # how far series spread about a position, a fraction of a step


def value_order(v):
    """A sort key putting any parameter values in one deterministic order: missing, booleans,
    numbers, strings, then anything else by its repr."""
    if v is None:
        return (0, 0.0, "")
    if isinstance(v, bool):
        return (1, float(v), "")
    if isinstance(v, (int, float)):
        return (2, float(v), "")
    if isinstance(v, str):
        return (3, 0.0, v)
    return (4, 0.0, repr(v))


def label(v, among=()) -> str:
    """A parameter value as a short label; paths (files, launch files) by what tells them apart
    ``among`` the values of the same parameter: their common leading folders and trailing
    parts left out (``students/alice/launch/avoid.launch`` and ``reference/launch/avoid.launch``
    become ``students/alice`` and ``reference``)."""
    if isinstance(v, float):
        return f"{v:g}"
    text = str(v)
    paths = [str(a).split("/") for a in among if isinstance(a, str) and "/" in a]
    if "/" not in text or len(paths) < 2 or len(paths) != len(among):
        return os.path.basename(text) if "/" in text else text
    head = 0
    while all(len(p) > head + 1 and p[head] == paths[0][head] for p in paths):
        head += 1
    tail = 0
    while all(len(p) > head + tail + 1 and p[-1 - tail] == paths[0][-1 - tail] for p in paths):
        tail += 1
    parts = text.split("/")
    kept = "/".join(parts[head:len(parts) - tail])
    return os.path.splitext(kept)[0] if tail == 0 else kept


def _legend(ax):
    """Below the axes, out of the data's way."""
    ax.legend(fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=1,
              frameon=False)


def _is_numeric(values):
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)


def _positions(values):
    """x of each distinct value, the axis' ticks and their labels, the distance between
    neighbouring positions."""
    distinct = sorted({value_order(v): v for v in values}.items())
    distinct = [v for _k, v in distinct]
    if _is_numeric(distinct):
        x = {value_order(v): float(v) for v in distinct}
        span = (max(x.values()) - min(x.values())) if len(x) > 1 else 1.0
        return x, None, None, span / max(1, len(x) - 1)
    x = {value_order(v): float(i) for i, v in enumerate(distinct)}
    return x, list(x.values()), [label(v, distinct) for v in distinct], 1.0


def _save(fig, path):
    fig.tight_layout()
    FigureCanvasAgg(fig).print_png(path)
    return os.path.basename(path)


def _groups(items, key):
    """Items grouped by ``key(item)`` in the keys' sorted order."""
    groups = {}
    for item in items:
        groups.setdefault(tuple(value_order(v) for v in key(item)), (key(item), []))[1].append(item)
    return [groups[k] for k in sorted(groups)]


def plot_against(path, summary, metric, param, series_params=(), note=""):
    """``metric``'s mean and 95 % interval per cell against ``param``, one line per value of
    ``series_params`` (the other varied parameters). Returns the file's name."""
    rows = [r for r in summary if r["metric"] == metric and np.isfinite(r["mean"])]
    x, ticks, tick_labels, step = _positions([r[f"param.{param}"] for r in rows])
    series = _groups(rows, lambda r: [r[f"param.{q}"] for q in series_params])
    fig = Figure(figsize=FIGURE_SIZE_IN, dpi=FIGURE_DPI)
    ax = fig.add_subplot(1, 1, 1)
    for k, (values, members) in enumerate(series):
        offset = DODGE * step * (k - 0.5 * (len(series) - 1)) / max(1, len(series))
        members.sort(key=lambda r: value_order(r[f"param.{param}"]))
        xs = np.array([x[value_order(r[f"param.{param}"])] for r in members]) + offset
        mean = np.array([r["mean"] for r in members], dtype=float)
        low = np.nan_to_num(mean - np.array([r["ci95_low"] for r in members], dtype=float))
        high = np.nan_to_num(np.array([r["ci95_high"] for r in members], dtype=float) - mean)
        text = ", ".join(f"{q}={label(v, _distinct(rows, q))}"
                         for q, v in zip(series_params, values))
        # a line between categories would suggest an order they do not have
        ax.errorbar(xs, mean, yerr=[low, high], fmt="o" if ticks else "o-", capsize=3,
                    label=text or None)
    if not rows:
        _no_values(ax)
    if ticks is not None:
        ax.set_xticks(ticks)
        ax.set_xticklabels(tick_labels)
    ax.set_xlabel(param)
    ax.set_ylabel(metric)
    ax.set_title(f"{metric}: mean and 95 % interval{note}", fontsize="medium")
    if series_params:
        _legend(ax)
    return _save(fig, path)


def plot_seeds(path, rows, metric, cell_params):
    """Each ok run's ``metric`` against its seed, one marker series per parameter cell (one
    series for all when there are more than MAX_SERIES cells). Returns the file's name."""
    ok = [r for r in rows if r.get("status") == "ok"
          and np.isfinite(as_number(r.get(f"metric.{metric}")))]
    cells = _groups(ok, lambda r: [r.get(f"param.{q}") for q in cell_params])
    if len(cells) > MAX_SERIES:
        cells = [((), ok)]
    fig = Figure(figsize=FIGURE_SIZE_IN, dpi=FIGURE_DPI)
    ax = fig.add_subplot(1, 1, 1)
    for values, members in cells:
        seeds = [float(r.get("seed", np.nan)) for r in members]
        y = [as_number(r.get(f"metric.{metric}")) for r in members]
        text = ", ".join(f"{q}={label(v, _distinct(ok, q))}" for q, v in zip(cell_params, values))
        ax.plot(seeds, y, "o", alpha=0.7, label=text or "runs")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("seed")
    ax.set_ylabel(metric)
    ax.set_title(f"{metric}: every run", fontsize="medium")
    if not ok:
        _no_values(ax)
    if len(cells) > 1:
        _legend(ax)
    return _save(fig, path)


def _distinct(rows, param):
    return list({value_order(r.get(f"param.{param}")): r.get(f"param.{param}")
                 for r in rows}.values())


def _no_values(ax):
    ax.text(0.5, 0.5, "no run has a value", transform=ax.transAxes, ha="center", va="center")


def as_number(v) -> float:
    """A metric's value as a float; NaN for a missing or non-numeric one."""
    try:
        return float(v)
    except (TypeError, ValueError):
        return np.nan

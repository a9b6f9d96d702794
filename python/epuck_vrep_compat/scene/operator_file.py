"""The ``cell.operator`` section of a scene file: the walking operator's body and its motion,
which is exactly one of

- ``waypoints_m`` (with ``speed_m_s``): a polyline walked to its end and back, over and over;
- ``walk``: a seeded random walk in the cell (``WalkSpec``), generated when the cell is built
  from its own seed, so the same walk seed gives the same walk under any simulation seed;
- ``trace``: a recorded trace replayed exactly, a CSV file of ``t,x,y,heading`` (seconds from
  the simulation's start, metres in the world frame, radians; :func:`read_trace`).

Malformed entries raise :class:`SceneError` naming the key (and, for a trace, its file and row).
"""
import csv
import math
import os
from dataclasses import dataclass, field, replace
from typing import List, Optional, Tuple

import numpy as np

from epuck_vrep_compat.scene.validation import (SceneError, as_list, color, number, numbers, only,
                                                positive)

TRACE_COLUMNS = ("t", "x", "y", "heading")
MOTIONS = ("waypoints_m", "walk", "trace")


@dataclass
class WalkSpec:
    """A seeded random walk: per leg a goal (with ``approach_probability`` one near a robot's
    base, at ``approach_distance_m`` from it, the robots in turn; else anywhere on the floor), a
    speed drawn from ``speed_m_s`` and a pause drawn from ``pause_s`` at the goal."""
    seed: int
    speed_m_s: Tuple[float, float] = (0.3, 2.0)       # ISO/TS 15066's walking speeds
    pause_s: Tuple[float, float] = (0.0, 2.0)
    approach_probability: float = 0.5
    legs: int = 20
    approach_distance_m: Tuple[float, float] = (0.5, 1.0)   # goal from the robot's base


@dataclass
class OperatorTrace:
    """A recorded trace: its file and its rows as arrays (``t`` strictly increasing), with each
    row's number in the file (the header is row 1)."""
    path: str
    t_s: np.ndarray
    x_m: np.ndarray
    y_m: np.ndarray
    heading_rad: np.ndarray
    rows: np.ndarray


@dataclass
class OperatorSpec:
    """The walking operator: its motion (one of waypoints, walk, trace) and its body."""
    name: str = "Bill"
    waypoints_m: List[Tuple[float, float]] = field(default_factory=list)
    speed_m_s: float = 1.2                       # along the waypoints
    walk: Optional[WalkSpec] = None
    trace: Optional[OperatorTrace] = None
    body_radius_m: float = 0.2
    body_height_m: float = 1.3
    head_radius_m: float = 0.11
    color: Tuple[float, float, float] = (0.1, 0.8, 0.2)


def parse_operator(d, where: str, base_dir: str) -> OperatorSpec:
    """The operator of the mapping ``d`` at ``where``; a trace's relative path resolves against
    ``base_dir`` (the scene file's folder)."""
    if not isinstance(d, dict):
        raise SceneError(f"{where} must be a mapping")
    only(d, {"name", "speed_m_s", "body_radius_m", "body_height_m", "head_radius_m", "color",
             *MOTIONS}, where)
    name = d.get("name")
    if "name" not in d or not isinstance(name, str) or not name:
        raise SceneError(f"{where}.name must be a non-empty string, got {name!r}")
    o = OperatorSpec(name=name)
    given = [k for k in MOTIONS if k in d]
    if len(given) != 1:
        raise SceneError(f"{where} needs exactly one of {list(MOTIONS)} (its motion), got "
                         f"{given or 'none'}")
    if "speed_m_s" in d and given[0] != "waypoints_m":
        raise SceneError(f"{where}.speed_m_s goes with waypoints_m; a walk draws its speeds from "
                         "walk.speed_m_s, a trace has its own")
    if "waypoints_m" in d:
        o.waypoints_m = _waypoints(d["waypoints_m"], f"{where}.waypoints_m")
        o.speed_m_s = positive(d.get("speed_m_s", o.speed_m_s), f"{where}.speed_m_s")
    elif "walk" in d:
        o.walk = parse_walk(d["walk"], f"{where}.walk")
    else:
        o.trace = trace_file(d["trace"], f"{where}.trace", base_dir)
    for key in ("body_radius_m", "body_height_m", "head_radius_m"):
        setattr(o, key, positive(d.get(key, getattr(o, key)), f"{where}.{key}"))
    o.color = color(d.get("color", o.color), f"{where}.color")
    return o


def _waypoints(v, where):
    points = [tuple(numbers(p, 2, f"{where}[{i}]")) for i, p in enumerate(as_list(v, where))]
    if len(points) < 2:
        raise SceneError(f"{where} needs at least 2 points")
    for i in range(1, len(points)):
        if points[i] == points[i - 1]:
            raise SceneError(f"{where}[{i}] repeats the point before it")
    return points


def seed_value(v, where) -> int:
    """A walk's seed: a non-negative integer (numpy's generators take no other)."""
    if isinstance(v, bool) or not isinstance(v, int) or v < 0:
        raise SceneError(f"{where} must be a non-negative integer, got {v!r}")
    return v


def parse_walk(d, where) -> WalkSpec:
    """A ``walk:`` mapping; ``seed`` is required, the rest have the defaults of WalkSpec."""
    if not isinstance(d, dict):
        raise SceneError(f"{where} must be a mapping such as {{seed: 1}}")
    only(d, {"seed", "speed_m_s", "pause_s", "approach_probability", "legs",
             "approach_distance_m"}, where)
    if "seed" not in d:
        raise SceneError(f"{where}.seed is required (the walk's own seed)")
    w = WalkSpec(seed_value(d["seed"], f"{where}.seed"))
    w.speed_m_s = _interval(d.get("speed_m_s", w.speed_m_s), f"{where}.speed_m_s", 0.0, False)
    w.pause_s = _interval(d.get("pause_s", w.pause_s), f"{where}.pause_s", 0.0, True)
    w.approach_distance_m = _interval(d.get("approach_distance_m", w.approach_distance_m),
                                      f"{where}.approach_distance_m", 0.0, False)
    w.approach_probability = number(d.get("approach_probability", w.approach_probability),
                                    f"{where}.approach_probability")
    if not 0.0 <= w.approach_probability <= 1.0:
        raise SceneError(f"{where}.approach_probability must be in 0..1, got "
                         f"{w.approach_probability}")
    legs = d.get("legs", w.legs)
    if isinstance(legs, bool) or not isinstance(legs, int) or not 1 <= legs <= 100000:
        raise SceneError(f"{where}.legs must be an integer in 1..100000, got {legs!r}")
    w.legs = legs
    return w


def _interval(v, where, low, low_allowed):
    """[lo, hi], low <= lo <= hi (lo == low only when ``low_allowed``)."""
    lo, hi = numbers(v, 2, where)
    if lo < low or (lo == low and not low_allowed) or hi < lo:
        bound = ">=" if low_allowed else ">"
        raise SceneError(f"{where} must be [lo, hi] with {bound} {low} lo <= hi, got {v!r}")
    return (lo, hi)


def trace_file(v, where, base_dir) -> OperatorTrace:
    """The trace named by ``v`` (a path; relative to ``base_dir``), read and checked."""
    if not isinstance(v, str) or not v:
        raise SceneError(f"{where} must name a CSV file, got {v!r}")
    path = v if os.path.isabs(v) else os.path.normpath(os.path.join(base_dir, v))
    return read_trace(path)


def read_trace(path: str) -> OperatorTrace:
    """A trace CSV: a header row ``t,x,y,heading``, then one row per sample of finite numbers,
    ``t`` >= 0 and strictly increasing. SceneError naming the file, the row and the problem."""
    try:
        with open(path, "r", encoding="utf-8", newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise SceneError(f"operator trace '{path}': cannot read it ({e.strerror})") from e
    except (UnicodeDecodeError, csv.Error) as e:
        raise SceneError(f"operator trace '{path}': not a UTF-8 CSV file ({e})") from e
    header = [c.strip() for c in rows[0]] if rows else []
    if tuple(header) != TRACE_COLUMNS:
        raise SceneError(f"operator trace '{path}' row 1: the header must be "
                         f"'{','.join(TRACE_COLUMNS)}', got '{','.join(header)}'")
    values, numbers_ = [], []
    for line, row in enumerate(rows[1:], start=2):
        if not row or all(not c.strip() for c in row):
            continue                                  # a blank line (e.g. at the end)
        values.append(_trace_row(path, line, row, values[-1][0] if values else None))
        numbers_.append(line)
    if not values:
        raise SceneError(f"operator trace '{path}': no rows after the header")
    t, x, y, heading = np.array(values, dtype=float).T
    return OperatorTrace(path, t, x, y, heading, np.array(numbers_))


def check_on_floor(spec: OperatorSpec, arena_size_m):
    """SceneError when the operator's trace leaves the arena's floor (centred on the origin):
    most likely not metres in the world frame (millimetres, or the capture's own origin)."""
    tr = spec.trace
    if tr is None:
        return
    hx, hy = 0.5 * arena_size_m[0], 0.5 * arena_size_m[1]
    outside = np.flatnonzero((np.abs(tr.x_m) > hx) | (np.abs(tr.y_m) > hy))
    if outside.size:
        i = outside[0]
        raise SceneError(f"operator trace '{tr.path}' row {tr.rows[i]}: ({tr.x_m[i]:g}, "
                         f"{tr.y_m[i]:g}) is outside the cell's floor [{-hx:g}, {hx:g}] x "
                         f"[{-hy:g}, {hy:g}] m (x, y in metres, in the world frame)")


def _trace_row(path, line, row, t_before):
    where = f"operator trace '{path}' row {line}"
    if len(row) != len(TRACE_COLUMNS):
        raise SceneError(f"{where}: expected {len(TRACE_COLUMNS)} values "
                         f"({','.join(TRACE_COLUMNS)}), got {len(row)}")
    values = []
    for name, cell in zip(TRACE_COLUMNS, row):
        try:
            v = float(cell)
        except ValueError:
            raise SceneError(f"{where}: {name} is not a number: {cell.strip()!r}") from None
        if not math.isfinite(v):
            raise SceneError(f"{where}: {name} is not finite: {cell.strip()!r}")
        values.append(v)
    t = values[0]
    if t_before is None and t < 0.0:
        raise SceneError(f"{where}: t must start at >= 0 s (seconds from the simulation's "
                         f"start; shift the recording's clock), got {t}")
    if t_before is not None and t <= t_before:
        raise SceneError(f"{where}: t must increase, got {t} after {t_before}")
    return values


def override_motion(spec: OperatorSpec, walk_seed: Optional[int] = None,
                    trace: Optional[str] = None, base_dir: str = ".") -> OperatorSpec:
    """``spec`` with its motion replaced (a launch's choice over the scene's): ``walk_seed``,
    the scene's walk under that seed (or a walk of WalkSpec's defaults when the scene's
    operator walks waypoints or a trace); ``trace``, that CSV file (relative to ``base_dir``).
    At most one of them; neither: ``spec`` itself. SceneError for an unusable one."""
    if walk_seed is not None and trace is not None:
        raise SceneError("give a walk seed or a trace for the operator, not both")
    if walk_seed is None and trace is None:
        return spec
    motion = dict(waypoints_m=[], walk=None, trace=None)
    if walk_seed is not None:
        seed = seed_value(walk_seed, "the operator's walk seed")
        motion["walk"] = replace(spec.walk, seed=seed) if spec.walk else WalkSpec(seed)
    else:
        motion["trace"] = trace_file(trace, "the operator's trace", base_dir)
    return replace(spec, **motion)

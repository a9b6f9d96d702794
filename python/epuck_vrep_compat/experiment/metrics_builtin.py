"""The built-in metrics of an experiment (see ``metrics``, whose ``compute`` runs them): each a
function of a run's context and its checked options, with its options' checks and defaults,
its columns and the topics it needs recorded.

A run's context is duck-typed (``metrics.RunContext``: ``recording``, ``robots``, ``world``) so
that this module does not import the one that calls it. Ground truth is ``/<robot>/ground_truth``
(``nav_msgs/Odometry``, every step); the robot is a disk of ``EPUCK_RADIUS_M``. Units: metres,
seconds of simulated time as stamped, m/s². The metrics [options] → columns:

- distance_driven [robots] → distance_driven_m: the robots' mean ground-truth path length
- collisions [robots, margin_m=0.002] → collisions, collisions_wall, collisions_obstacle,
  collisions_robot (contact onsets: gap <= margin_m; per robot and kind, per robot pair),
  time_in_contact_s (robot-seconds touching anything)
- coverage [robots, cell_m=0.05] → coverage: fraction of grid cells whose centre a disk covered
- time_to_region [region, robots, all=false] → time_to_region_s: first stamp a centre is in it
- min_separation [robots] → min_separation_m: closest centres of any pair (NaN for one robot)
- imu_stats [robot, window_s] → accel_{x,y,z}_{mean,sd}: ``/<robot>/imu`` or ``/accel``
- ir_stats [robot, sensor, window_s] → ir<k>_wrong_fraction, ir<k>_mean_m, ir<k>_sd_m
- topic_stat [topic, field, stat, name, window_s] → <name>

``robots`` defaults to every robot of the run, ``robot`` to the first, ``window_s`` [t0, t1]
to the whole run (both ends included); every metric also takes ``prefix``.
"""
import math
import re
from typing import Callable, Dict, NamedTuple

import numpy as np

from epuck_vrep_compat.experiment import metrics_geometry as geo
from epuck_vrep_compat.experiment.metrics_geometry import finite_number
from epuck_vrep_compat.fidelity.stats import mean_and_sd

X, Y = "pose.pose.position.x", "pose.pose.position.y"
WRONG_TOLERANCE_M = 1e-6        # a reading this far below max range is "wrong" (fit_ir's)
STATS = ("mean", "sd", "min", "max", "last", "count", "rate_hz")
COLUMN_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.]*$")


def series(ctx, topic: str):
    """A recorded topic; KeyError listing the recorded topics."""
    if topic not in ctx.recording:
        raise KeyError(f"topic {topic} was not recorded; recorded: "
                       f"{', '.join(sorted(ctx.recording)) or 'none'}")
    return ctx.recording[topic]


def _robots(ctx, o):
    robots = o["robots"] if o["robots"] is not None else ctx.robots
    if not robots:
        raise ValueError("no robots: the recording has no /<robot>/ground_truth topic")
    return robots


def _xy(ctx, robot):
    s = series(ctx, f"/{robot}/ground_truth")
    return s.t, np.stack([s.field(X), s.field(Y)], axis=1)


def _positions(ctx, robots):
    """Stamps common to every robot's ground truth and the (R, T, 2) positions at them."""
    tracks = [_xy(ctx, r) for r in robots]
    t = tracks[0][0]
    for other_t, _ in tracks[1:]:
        t = np.intersect1d(t, other_t)
    if t.size == 0:
        raise ValueError("the robots' ground truths share no instant")
    return t, np.stack([xy[np.searchsorted(tt, t)] for tt, xy in tracks])


def _window(o, s):
    t0, t1 = o["window_s"] if o["window_s"] is not None else (-math.inf, math.inf)
    mask = (s.t >= t0) & (s.t <= t1)
    if not mask.any():
        raise ValueError(f"no message in the window {[t0, t1]} s")
    return mask


def _distance_driven(ctx, o):
    lengths = [np.sum(np.hypot(*np.diff(_xy(ctx, r)[1], axis=0).T)) for r in _robots(ctx, o)]
    return {"distance_driven_m": float(np.mean(lengths))}


def _collisions(ctx, o):
    robots, margin = _robots(ctx, o), o["margin_m"]
    t, xy = _positions(ctx, robots)
    shapes = geo.shapes_of(ctx.world)
    counts = {"wall": 0, "obstacle": 0, "robot": 0}
    touching = np.zeros((len(robots), t.size), dtype=bool)
    for k in range(len(robots)):
        wall, obstacle = geo.clearances(shapes, xy[k])
        counts["wall"] += geo.onsets(wall <= margin)
        counts["obstacle"] += geo.onsets(obstacle <= margin)
        touching[k] = (wall <= margin) | (obstacle <= margin)
    for (i, j), d in geo.pair_distances(xy):
        contact = d - 2.0 * geo.EPUCK_RADIUS_M <= margin
        counts["robot"] += geo.onsets(contact)     # one event for the pair
        touching[i] |= contact
        touching[j] |= contact
    out = {"collisions": float(sum(counts.values()))}
    out.update((f"collisions_{kind}", float(n)) for kind, n in counts.items())
    out["time_in_contact_s"] = sum(geo.held_time_s(t, row) for row in touching)
    return out


def _coverage(ctx, o):
    xy = np.concatenate([_xy(ctx, r)[1] for r in _robots(ctx, o)])
    return {"coverage": geo.coverage_fraction(ctx.world, xy, o["cell_m"])}


def _time_to_region(ctx, o):
    firsts = []
    for robot in _robots(ctx, o):
        t, xy = _xy(ctx, robot)
        inside = geo.inside_region(o["region"], xy)
        firsts.append(float(t[np.argmax(inside)]) if inside.any() else math.nan)
    if o["all"]:
        value = max(firsts) if not any(map(math.isnan, firsts)) else math.nan
    else:
        value = min((f for f in firsts if not math.isnan(f)), default=math.nan)
    return {"time_to_region_s": value}


def _min_separation(ctx, o):
    robots = _robots(ctx, o)
    if len(robots) < 2:
        return {"min_separation_m": math.nan}
    _, xy = _positions(ctx, robots)
    return {"min_separation_m": float(min(d.min() for _pair, d in geo.pair_distances(xy)))}


def _robot(ctx, o):
    if o["robot"] is not None:
        return o["robot"]
    return _robots(ctx, {"robots": None})[0]


def _imu_stats(ctx, o):
    robot = _robot(ctx, o)
    topic = next((t for t in (f"/{robot}/imu", f"/{robot}/accel") if t in ctx.recording),
                 f"/{robot}/imu")
    s = series(ctx, topic)
    mask = _window(o, s)
    out = {}
    for axis in "xyz":
        mean, sd = mean_and_sd(s.field(f"linear_acceleration.{axis}")[mask])
        out[f"accel_{axis}_mean"], out[f"accel_{axis}_sd"] = mean["value"], sd["value"]
    return out


def _ir_stats(ctx, o):
    k = o["sensor"]
    s = series(ctx, f"/{_robot(ctx, o)}/proximity{k}")
    mask = _window(o, s)
    reading = s.field("range")[mask]
    wrong = reading < s.field("max_range")[mask] - WRONG_TOLERANCE_M
    mean, sd = mean_and_sd(reading)
    return {f"ir{k}_wrong_fraction": float(wrong.mean()), f"ir{k}_mean_m": mean["value"],
            f"ir{k}_sd_m": sd["value"]}


def _topic_stat(ctx, o):
    s = series(ctx, o["topic"])
    mask = _window(o, s)
    t, stat = s.t[mask], o["stat"]
    if stat == "count":
        value = float(t.size)
    elif stat == "rate_hz":
        value = (t.size - 1) / (t[-1] - t[0]) if t[-1] > t[0] else math.nan
    else:
        if o["field"] is None:
            raise ValueError(f"stat {stat} needs a field")
        v = s.field(o["field"])[mask]
        value = {"mean": np.mean, "sd": lambda a: np.std(a, ddof=1) if a.size > 1 else math.nan,
                 "min": np.min, "max": np.max, "last": lambda a: a[-1]}[stat](v)
    return {o["name"]: float(value)}


# the options' checks: each returns the value to use or raises ValueError saying what is wrong
def _number(low, strict):
    def check(v):
        if not finite_number(v) or (v <= low if strict else v < low):
            raise ValueError(f"must be a number {'>' if strict else '>='} {low}, got {v!r}")
        return float(v)
    return check


def _one_of(choices, what):
    def check(v):
        # by type too: YAML's true is not the sensor 1, nor 1.0 a sensor
        if not any(type(v) is type(c) and v == c for c in choices):
            raise ValueError(f"must be {what}, got {v!r}")
        return v
    return check


def _name(v):
    if not isinstance(v, str) or not v.strip("/"):
        raise ValueError(f"must be a robot's namespace such as ePuck0, got {v!r}")
    return v.strip("/")


def _names(v):
    if not isinstance(v, (list, tuple)) or not v:
        raise ValueError(f"must be a non-empty list of robot namespaces, got {v!r}")
    return [_name(r) for r in v]


def _window_s(v):
    ok = isinstance(v, (list, tuple)) and len(v) == 2 and all(
        isinstance(x, (int, float)) and not isinstance(x, bool) and not math.isnan(x) for x in v)
    if not ok or v[0] > v[1]:
        raise ValueError(f"must be [t0, t1] in seconds with t0 <= t1, got {v!r}")
    return [float(v[0]), float(v[1])]


def _text(pattern, what):
    def check(v):
        if not isinstance(v, str) or not re.match(pattern, v):
            raise ValueError(f"must be {what}, got {v!r}")
        return v
    return check


def _topics(v):
    if not isinstance(v, (list, tuple)):
        raise ValueError(f"must be a list of topic patterns, got {v!r}")
    return [_text(r"^/", "an absolute topic pattern")(p) for p in v]


REQUIRED = object()
_PREFIX = (_text(r"^[A-Za-z0-9_.]*$", "letters, digits, '_' or '.'"), "")
_ROBOTS, _ROBOT, _WINDOW = (_names, None), (_name, None), (_window_s, None)


class _Metric(NamedTuple):
    compute: Callable
    options: Dict[str, tuple]          # option -> (check, default or REQUIRED)
    columns: Callable                  # checked options -> column names
    topics: Callable                   # checked options -> topic patterns to record


def _per_robot(o, *names):
    robots = o.get("robots") or ([o["robot"]] if o.get("robot") else ["*"])
    return [f"/{r}/{n}" for r in robots for n in names]


def _ground_truth(compute, columns, **options):
    return _Metric(compute, dict(robots=_ROBOTS, prefix=_PREFIX, **options),
                   lambda o: columns, lambda o: _per_robot(o, "ground_truth"))


BUILTIN = {
    "distance_driven": _ground_truth(_distance_driven, ["distance_driven_m"]),
    "collisions": _ground_truth(
        _collisions, ["collisions", "collisions_wall", "collisions_obstacle",
                      "collisions_robot", "time_in_contact_s"],
        margin_m=(_number(0, False), 0.002)),
    "coverage": _ground_truth(_coverage, ["coverage"], cell_m=(_number(0, True), 0.05)),
    "time_to_region": _ground_truth(
        _time_to_region, ["time_to_region_s"], region=(geo.check_region, REQUIRED),
        all=(_one_of((True, False), "true or false"), False)),
    "min_separation": _ground_truth(_min_separation, ["min_separation_m"]),
    "imu_stats": _Metric(
        _imu_stats, dict(robot=_ROBOT, window_s=_WINDOW, prefix=_PREFIX),
        lambda o: [f"accel_{a}_{s}" for a in "xyz" for s in ("mean", "sd")],
        lambda o: _per_robot(o, "imu", "accel")),
    "ir_stats": _Metric(
        _ir_stats, dict(robot=_ROBOT, sensor=(_one_of(range(8), "a sensor 0..7"), REQUIRED),
                        window_s=_WINDOW, prefix=_PREFIX),
        lambda o: [f"ir{o['sensor']}_{c}" for c in ("wrong_fraction", "mean_m", "sd_m")],
        lambda o: _per_robot(o, f"proximity{o['sensor']}")),
    "topic_stat": _Metric(
        _topic_stat, dict(topic=(_text(r"^/", "an absolute topic name"), REQUIRED),
                          field=(_text(r"^\w", "a field path"), None),
                          stat=(_one_of(STATS, f"one of {', '.join(STATS)}"), REQUIRED),
                          name=(_text(COLUMN_NAME.pattern, "a column name"), REQUIRED),
                          window_s=_WINDOW, prefix=_PREFIX),
        lambda o: [o["name"]], lambda o: [o["topic"]]),
}
# a user-defined metric: f(ctx) -> float (column: the metric's name) or {column: float}; the
# spec reader marks it ``custom: true`` and may keep where its function came from
CUSTOM = _Metric(None, dict(custom=(_one_of((True,), "true"), True),
                            function=(_text(r".", "FILE.py:FUNCTION or MODULE:FUNCTION"), None),
                            topics=(_topics, []), prefix=_PREFIX),
                 None, lambda o: o["topics"])

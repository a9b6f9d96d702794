"""The safety benchmark's metrics per walk (``experiments/safety_ssm.yaml``), from what a run
recorded: ``/safety_bench/truth`` (every step, from ``bench_truth``: x = the robot's true
minimum separation from the operator, the core's distance; y = v_r, its fastest link's speed
at its closest point; z = the tracker's error), ``/<robot>/speed_scale`` (the monitor's
command, recorded at the step it answered) and ``/<robot>/safety_stop`` (the simulator's
watchdog). Units: metres, seconds of simulated time, steps of the recording.

- S_p(t) is the standard's protective separation for the robot's true speed at that instant,
  with the monitor's parameters (T_r, T_s, C, v_h, Z_r; ``monitor.<name>`` of the run's
  parameters, else :class:`SsmParameters`' defaults) and Z_d = 0 (the true position);
- in violation: separation < S_p(t) while the robot moves (v_r > ``MOVING_M_S``; a robot at
  rest has stopped, which is what the standard asks of it);
- a contact: the separation falling to ``CONTACT_M`` or less while the robot moves (an
  onset); ``touches``: any onset, the robot moving or not (the operator walks through it);
- the scale in effect: the last speed_scale at or before the step, 0 while the watchdog's
  safety_stop holds, 1 before any; productivity = its mean over the walk (task progress
  with the operator against without: the scale slows the task's clock), and the cycle-time
  ratio its inverse; ``protective_stop_s`` the time at scale 0, ``final_scale`` the last;
- reaction, per approach (as ``bench/cell_bench.py --safety``): from the first step the
  separation is below S_p(t) to the first step with the scale in effect below 1 (negative:
  the slow-down came first, as it should); an approach ends when the operator is outside
  S_p and the scale is back to 1. Only a slow-down that starts after the scale was 1 counts:
  a scale below 1 since the walk's start (the lock-step handshake's latched 0, a monitor that
  never released the robot) is no reaction to this breach, and would read as a large negative,
  i.e. good, one. A walk's reaction is its worst approach's (NaN: never reduced after being
  1, or never breached).
"""
import math

import numpy as np

from epuck_vrep_compat.experiment.metrics_geometry import held_time_s, onsets
from epuck_vrep_compat.nodes.ssm_model import SsmParameters, protective_separation

TRUTH_TOPIC = "/safety_bench/truth"
MOVING_M_S = 0.005
CONTACT_M = 0.001
# stamps are whole nanoseconds; as float seconds a command's stamp and the step's time it
# answers may differ by rounding, below a nanosecond: this much later still counts as "at"
STAMP_TOLERANCE_S = 1e-9
PARAM_PREFIX = "monitor."
COLUMNS = ("min_separation_m", "violation_s", "violation_steps", "contacts", "touches",
           "reaction_steps", "reaction_s", "productivity", "cycle_time_ratio",
           "protective_stop_s", "final_scale", "tracker_error_mean_m", "tracker_error_p95_m")


def monitor_parameters(params):
    """SsmParameters from a run's parameters (``monitor.reaction_time_s`` ...), the rest
    at their defaults."""
    p = SsmParameters()
    for name in vars(SsmParameters()):
        if PARAM_PREFIX + name in params:
            setattr(p, name, float(params[PARAM_PREFIX + name]))
    return p


def scale_in_effect(t, scale_t=(), scale=(), stop_t=(), stop=()):
    """The speed scale the robot had at each instant of ``t``: the last command at or before
    it (1 before any), 0 while the last safety_stop at or before it is true."""
    t = np.asarray(t, dtype=float)
    out = _last_at(t, scale_t, scale, 1.0)
    out = np.where(_last_at(t, stop_t, stop, 0.0) > 0.5, 0.0, out)
    return np.clip(np.nan_to_num(out, nan=0.0), 0.0, 1.0)


def _last_at(t, times, values, before):
    """At each instant of ``t``, the last of ``values`` stamped at or before it (``times``
    sorted), ``before`` where none is."""
    if not len(times):
        return np.full_like(t, before)
    i = np.searchsorted(np.asarray(times), t + STAMP_TOLERANCE_S, side="right") - 1
    return np.where(i >= 0, np.asarray(values, dtype=float)[np.maximum(i, 0)], before)


def reactions(inside, scale):
    """Per approach, the steps from the first step ``inside`` (below S_p) to the first step
    with ``scale`` < 1 that follows a scale of 1 (negative: it came first); see the module's
    docstring."""
    out, crossed, slowed = [], None, None
    measured = was_full = False
    for k, (is_inside, s) in enumerate(zip(inside, scale)):
        slow = s < 1.0
        if slowed is None and slow and was_full:
            slowed = k
        was_full = not slow
        if crossed is None and is_inside:
            crossed = k
        if not measured and crossed is not None and slowed is not None:
            out.append(slowed - crossed)
            measured = True
        if not slow and not is_inside:
            crossed = slowed = None
            measured = False
    return out


def walk_metrics(t, separation, robot_speed, tracker_error, applied_scale, p):
    """The columns of ``COLUMNS`` for one walk, from per-step arrays (see the module)."""
    t, d, v = (np.asarray(a, dtype=float) for a in (t, separation, robot_speed))
    if t.size < 2:
        raise ValueError("fewer than two steps of ground truth")
    step_s = float(np.median(np.diff(t)))
    s_p = np.array([protective_separation(p, 0.0, x) for x in np.nan_to_num(v)])
    moving = np.nan_to_num(v) > MOVING_M_S
    violation = (d < s_p) & moving
    touching = d <= CONTACT_M
    reaction = reactions(d < s_p, applied_scale)
    worst = max(reaction) if reaction else math.nan
    error = np.asarray(tracker_error, dtype=float)
    error = error[np.isfinite(error)]
    productivity = float(np.mean(applied_scale))
    return {
        "min_separation_m": float(np.min(d)),
        "violation_s": held_time_s(t, violation),
        "violation_steps": float(np.count_nonzero(violation)),
        "contacts": float(onsets(touching & moving)),
        "touches": float(onsets(touching)),
        "reaction_steps": float(worst),
        "reaction_s": float(worst * step_s),
        "productivity": productivity,
        "cycle_time_ratio": 1.0 / productivity if productivity > 0 else math.inf,
        "protective_stop_s": held_time_s(t, np.asarray(applied_scale) <= 0.0),
        "final_scale": float(applied_scale[-1]),
        "tracker_error_mean_m": float(np.mean(error)) if error.size else math.nan,
        "tracker_error_p95_m": float(np.percentile(error, 95)) if error.size else math.nan,
    }


def ssm_metrics(ctx, robot="IRB140"):
    """The benchmark's metric (``function: epuck_vrep_compat.experiment.metrics_safety:
    ssm_metrics`` in a spec): ``COLUMNS`` of one run's context."""
    truth = ctx.series(TRUTH_TOPIC)
    t = truth.t
    scale = ctx.recording.get(f"/{robot}/speed_scale")
    stop = ctx.recording.get(f"/{robot}/safety_stop")
    applied = scale_in_effect(t, *((scale.t, scale.field("data")) if scale else ((), ())),
                              *((stop.t, stop.field("data")) if stop else ((), ())))
    return walk_metrics(t, truth.field("vector.x"), truth.field("vector.y"),
                        truth.field("vector.z"), applied, monitor_parameters(ctx.params))

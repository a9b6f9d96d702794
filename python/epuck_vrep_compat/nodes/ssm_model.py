"""Speed and separation monitoring (ISO/TS 15066, 5.5.4), the arithmetic of ``ssm_supervisor``.

The protective separation distance, for a robot whose fastest link moves at v_r (m/s) and an
operator approaching at v_h:

    S_p = S_h + S_r + S_s + C + Z_d + Z_r
    S_h = v_h (T_r + T_s)      the operator's approach while the robot reacts and stops
    S_r = v_r T_r              the robot's motion while it reacts
    S_s = v_r T_s / 2          its stopping distance (constant deceleration over T_s)
    C                          intrusion distance (a body part reaching past the sensed body)
    Z_d                        the operator's position uncertainty (k sigma of the tracker)
    Z_r                        the robot's position uncertainty

S_p is linear in v_r: S_p = S_p0 + v_r (T_r + T_s / 2), with S_p0 = S_h + C + Z_d + Z_r. The
speed scale s in [0, 1] is the largest that keeps S_p(s v_ref) <= d for the separation d, where
v_ref is the robot's speed at full scale: s = (d - S_p0) / (v_ref (T_r + T_s / 2)). At s = 0
the robot is held (a protective stop), and it resumes once d >= S_p0 + resume_margin.

S_p must hold at every instant the robot moves, not only at the instants the separation was
measured: a scale computed from the separation d measured at t takes effect later and stays
until the next one does, the horizon h (the measurement's age when the cycle runs, plus one
cycle: the command's trip and its time in effect). Over h the operator approaches by up to
v_h h and the robot by up to v_r h, so the scale is chosen for the separation at the end of
the horizon, d - (v_h + s v_ref) h:

    s = (d - v_h h - S_p0) / (v_ref (T_r + T_s / 2 + h))

which keeps S_p(s v_ref) <= d - (v_h + s v_ref) h, and stops the robot (s = 0) once
d <= S_p0 + v_h h. With h = 0 it is the instantaneous rule above.

v_ref is learnt (the fastest speed seen per unit of scale, never less than its floor), so it
is only as good as what the robot has shown: an arm released from a stop may first close the
gap to its task's path at its joints' speed limits (the IRB 140 of the benchmark's cell: about
4.5 m/s per unit of scale, against the task's 1 m/s or less). So the scale rises gently: after a
stop to at most ``restart_scale``, and then at most doubling per cycle, while v_ref learns from
every cycle the robot moves; a robot that turns out fast has then moved only slowly. What it
learns it keeps for ``speed_memory_s`` (then back to the fastest since, at least the floor):
once the arm is back on its path it moves at its task's speed again, and a speed learnt from
the catching up would slow it for nothing (every stop restarts at ``restart_scale``, which
learns it again).
"""
import collections
import math
from dataclasses import dataclass

import numpy as np

HUMAN_SPEED_M_S = 1.6       # ISO 13855's walking speed, the standard's default for v_h
RISE_FACTOR = 2.0           # the scale at most doubles per cycle (from restart_scale)


@dataclass
class SsmParameters:
    """The supervisor's parameters (its private parameters of the same names)."""
    human_speed_m_s: float = HUMAN_SPEED_M_S
    reaction_time_s: float = 0.2      # T_r: sensing, the supervisor's cycle, the command's trip
    stopping_time_s: float = 0.3      # T_s: from the stop command to standstill
    intrusion_m: float = 0.1          # C
    robot_uncertainty_m: float = 0.02  # Z_r
    tracker_sigmas: float = 2.0       # Z_d = this many standard deviations of the estimate
    min_operator_uncertainty_m: float = 0.0   # Z_d floor (e.g. with ground truth)
    reference_speed_m_s: float = 1.0  # v_ref floor: the speed at which the scale reaches 1
    resume_margin_m: float = 0.05     # hysteresis after a protective stop
    restart_scale: float = 0.01       # the scale's first step after a stop (then it doubles)
    speed_memory_s: float = 2.0       # how long v_ref keeps a speed it learnt

    def check(self):
        """ValueError naming the first parameter that is not a finite number >= 0 (> 0 for
        reference_speed_m_s, in (0, 1] for restart_scale)."""
        for name, value in vars(self).items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError(f"~{name} must be a finite number >= 0, got {value!r}")
        if self.reference_speed_m_s <= 0:
            raise ValueError("~reference_speed_m_s must be > 0")
        if not 0 < self.restart_scale <= 1:
            raise ValueError("~restart_scale must be in (0, 1]")


def operator_uncertainty(p: SsmParameters, covariance_xy=None) -> float:
    """Z_d: k standard deviations along the estimate's worst direction (its 2x2 xy covariance's
    largest eigenvalue), at least the floor; the floor alone without a covariance."""
    if covariance_xy is None:
        return p.min_operator_uncertainty_m
    worst = float(np.linalg.eigvalsh(np.asarray(covariance_xy, dtype=float)).max())
    return max(p.min_operator_uncertainty_m, p.tracker_sigmas * math.sqrt(max(worst, 0.0)))


def static_separation(p: SsmParameters, z_d: float) -> float:
    """S_p0 = S_h + C + Z_d + Z_r: the protective separation of a robot at rest."""
    return (p.human_speed_m_s * (p.reaction_time_s + p.stopping_time_s) + p.intrusion_m + z_d
            + p.robot_uncertainty_m)


def protective_separation(p: SsmParameters, z_d: float, robot_speed_m_s: float) -> float:
    """S_p for the robot moving at robot_speed_m_s."""
    return static_separation(p, z_d) + robot_speed_m_s * (
        p.reaction_time_s + 0.5 * p.stopping_time_s)


class ArmGovernor:
    """One robot's speed scale from its separation, with the hold after a protective stop and
    the running estimate of its speed at full scale (v_ref)."""

    def __init__(self, p: SsmParameters):
        self.p = p
        self.reference_speed_m_s = p.reference_speed_m_s
        self._learnt = collections.deque()      # (time, speed per unit of scale), rising
        self.scale = 0.0            # until the first good cycle: fail safe
        self.stopped = True

    def learn_speed(self, speed_m_s: float, now_s: float = 0.0):
        """v_ref: the fastest speed per unit of scale seen within ``speed_memory_s`` before
        ``now_s``, at least the floor; the speed is the one the robot had under the scale last
        given (``self.scale``)."""
        learnt = self._learnt
        if self.scale > 0.0 and math.isfinite(speed_m_s):
            ratio = speed_m_s / self.scale
            while learnt and learnt[-1][1] <= ratio:        # kept: each slower than the last
                learnt.pop()
            learnt.append((now_s, ratio))
        while learnt and learnt[0][0] < now_s - self.p.speed_memory_s:
            learnt.popleft()
        self.reference_speed_m_s = max([self.p.reference_speed_m_s] + [r for _, r in learnt])

    def update(self, separation_m: float, z_d: float, horizon_s: float = 0.0) -> float:
        """The scale for this separation (NaN: 0) that keeps S_p within it until the end of
        ``horizon_s`` (see the module's docstring)."""
        if not math.isfinite(separation_m):
            self.scale, self.stopped = 0.0, True
            return self.scale
        h = max(float(horizon_s), 0.0) if math.isfinite(horizon_s) else 0.0
        s_p0 = static_separation(self.p, z_d) + self.p.human_speed_m_s * h
        band = self.reference_speed_m_s * (
            self.p.reaction_time_s + 0.5 * self.p.stopping_time_s + h)
        scale = min(1.0, max(0.0, (separation_m - s_p0) / band),
                    max(RISE_FACTOR * self.scale, self.p.restart_scale))
        if self.stopped and separation_m < s_p0 + self.p.resume_margin_m:
            scale = 0.0
        self.scale, self.stopped = scale, scale == 0.0
        return scale

    def stop(self):
        self.scale, self.stopped = 0.0, True

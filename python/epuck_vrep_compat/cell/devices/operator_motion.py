"""Where the operator is at time t: each of his motions as a pure function of the time since
the simulation started (or was reset), so that the same walk is the same, bit for bit, at any
real-time factor and under any monitor.

- :class:`PingPongPath`: a polyline walked at one speed to its end and back, over and over;
- :class:`TimedPath`: keyframes ``(t, x, y, heading)``, linearly interpolated (the heading along
  the shorter arc), held at the first before it starts and at the last after it ends; a
  recorded trace and a generated walk (:mod:`.operator_walk`) are both one.
"""
import math

import numpy as np

from epuck_vrep_compat.devices.components import wrap_angle


class PingPongPath:
    """A polyline of at least two distinct consecutive points, walked at ``speed_m_s``."""

    def __init__(self, points, speed_m_s: float):
        self.points = np.asarray(points, dtype=float)
        seg = np.diff(self.points, axis=0)
        self.lengths = np.hypot(seg[:, 0], seg[:, 1])
        if len(self.points) < 2 or not (self.lengths > 0.0).all():
            raise ValueError("operator waypoints: at least 2, none repeating the one before")
        self.cumulative = np.concatenate(([0.0], np.cumsum(self.lengths)))
        self.path_length = float(self.cumulative[-1])
        self.speed_m_s = float(speed_m_s)
        self.duration_s = math.inf              # it never ends

    def at(self, t_s: float):
        """(x, y, heading [rad], outbound?) after walking for ``t_s``."""
        lap = math.fmod(max(0.0, self.speed_m_s * t_s), 2.0 * self.path_length)
        outbound = lap <= self.path_length
        s = lap if outbound else 2.0 * self.path_length - lap
        i = int(np.clip(np.searchsorted(self.cumulative, s, side="right") - 1, 0,
                        len(self.lengths) - 1))
        a, b = self.points[i], self.points[i + 1]
        f = (s - self.cumulative[i]) / self.lengths[i]
        x, y = a + f * (b - a)
        heading = math.atan2(b[1] - a[1], b[0] - a[0])
        if not outbound:
            heading = math.atan2(-math.sin(heading), -math.cos(heading))
        return float(x), float(y), heading, outbound


class TimedPath:
    """Keyframes at non-decreasing times (two at one time: a jump, the later one holds)."""

    def __init__(self, t_s, x_m, y_m, heading_rad):
        self.t = np.asarray(t_s, dtype=float)
        self.xy = np.stack((np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float)), axis=1)
        self.heading = np.asarray(heading_rad, dtype=float)
        if not (len(self.t) == len(self.xy) == len(self.heading) >= 1):
            raise ValueError("a timed path needs at least one keyframe, every column as long")
        if (np.diff(self.t) < 0.0).any():
            raise ValueError("a timed path's times must not decrease")
        # the heading's change to the next keyframe, along the shorter arc
        self.turn = np.array([wrap_angle(d) for d in np.diff(self.heading)])
        self.duration_s = float(self.t[-1])

    def at(self, t_s: float):
        """(x, y, heading [rad], moving?) at time ``t_s``."""
        n = len(self.t)
        i = int(np.searchsorted(self.t, t_s, side="right")) - 1
        if i < 0 or i >= n - 1:                  # before the first or after the last: held
            k = 0 if i < 0 else n - 1
            x, y = self.xy[k]
            return float(x), float(y), wrap_angle(self.heading[k]), False
        span = self.t[i + 1] - self.t[i]         # > 0: i is the last keyframe at or before t_s
        f = (t_s - self.t[i]) / span
        a, b = self.xy[i], self.xy[i + 1]
        x, y = a + f * (b - a)
        heading = wrap_angle(self.heading[i] + f * self.turn[i])
        return float(x), float(y), heading, bool((a != b).any())


def trace_path(trace) -> TimedPath:
    """A recorded trace (:class:`~epuck_vrep_compat.scene.operator_file.OperatorTrace`)."""
    return TimedPath(trace.t_s, trace.x_m, trace.y_m, trace.heading_rad)

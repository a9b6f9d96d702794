"""Throttled warnings keyed by what they are about.

rospy's ``logwarn_throttle`` keys on the call site and counts ROS time: one robot's bad command
hides every other robot's (and every other kind of fault from the same line) for the period,
and a simulation running 10x real time repeats the line ten times as often. :class:`ThrottledLog`
keys on a caller-given key (robot, topic, kind of fault) and counts wall time, so a paused
simulation does not silence it either.
"""
import threading
import time
from typing import Dict

import rospy

WARN_PERIOD_S = 5.0


class ThrottledLog:
    """At most one warning per key and period (wall time)."""

    def __init__(self, period_s: float = WARN_PERIOD_S):
        self._period_s = period_s
        self._last: Dict[str, float] = {}
        self._lock = threading.Lock()

    def warn(self, key: str, fmt: str, *args):
        now = time.monotonic()
        with self._lock:
            last = self._last.get(key)
            if last is not None and now - last < self._period_s:
                return
            self._last[key] = now
        rospy.logwarn(fmt, *args)

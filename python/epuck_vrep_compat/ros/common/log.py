"""Throttled warnings keyed by what they are about.

rospy's ``logwarn_throttle`` keys on the call site and counts ROS time: one robot's bad command
hides every other robot's (and every other kind of fault from the same line) for the period,
and a simulation running 10x real time repeats the line ten times as often. :class:`ThrottledLog`
keys on a caller-given key (robot, topic, kind of fault) and counts wall time, so a paused
simulation does not silence it either. Keys may come from clients (a topic or joint name a request
named), so it remembers at most :data:`MAX_KEYS` of them: a key whose period has passed throttles
nothing and is forgotten first, and beyond that the oldest go (at worst one line more).
"""
import logging
import threading
import time
from typing import Dict

import rospy

WARN_PERIOD_S = 5.0
MAX_KEYS = 1000         # keys remembered; more distinct keys within one period: the oldest go


class ThrottledLog:
    """At most one line per key and period (wall time)."""

    def __init__(self, period_s: float = WARN_PERIOD_S, max_keys: int = MAX_KEYS):
        self._period_s = period_s
        self._max_keys = max_keys
        self._last: Dict[str, float] = {}       # key -> when it last logged, oldest first
        self._lock = threading.Lock()

    def warn(self, key: str, fmt: str, *args):
        if self._due(key):
            rospy.logwarn(fmt, *args)

    def error(self, key: str, fmt: str, *args):
        if self._due(key):
            rospy.logerr(fmt, *args)

    def _due(self, key: str) -> bool:
        now = time.monotonic()
        with self._lock:
            last = self._last.get(key)
            if last is not None and now - last < self._period_s:
                return False
            self._last.pop(key, None)
            self._last[key] = now
            if len(self._last) > self._max_keys:
                self._forget(now)
        return True

    def _forget(self, now: float):
        """Keys whose period has passed, then (a flood of distinct keys) the oldest, down to
        ``max_keys``."""
        expired = [k for k, t in self._last.items() if now - t >= self._period_s]
        for k in expired:
            del self._last[k]
        while len(self._last) > self._max_keys:
            del self._last[next(iter(self._last))]

    def __len__(self) -> int:
        """The keys remembered."""
        return len(self._last)


def serve_get_loggers_safely():
    """Make this node's ``~get_loggers`` answer every time.

    rospy's handler iterates ``logging.Logger.manager.loggerDict`` while other threads may
    create loggers (rospy makes some per connection), and then fails with "dictionary changed
    size during iteration"; it also fails on a level it has no name for. Call after
    ``rospy.init_node``: the registered service keeps its name and type, its handler becomes one
    that copies the logger table under logging's own lock first."""
    from rospy.impl.registration import get_service_manager
    service = get_service_manager().get_service(rospy.resolve_name("~get_loggers"))
    if service is not None:
        service.handler = _get_loggers


_LEVEL_NAMES = ((logging.CRITICAL, "FATAL"), (logging.ERROR, "ERROR"),
                (logging.WARNING, "WARN"), (logging.INFO, "INFO"), (logging.DEBUG, "DEBUG"))


def _level_name(level: int) -> str:
    """rosconsole's name of a logging level; a level between two named ones takes the lower."""
    return next((name for number, name in _LEVEL_NAMES if level >= number), "DEBUG")


def _get_loggers(_request):
    from roscpp.msg import Logger
    from roscpp.srv import GetLoggersResponse
    with logging._lock:          # the lock logging.getLogger holds while it adds a logger
        names = list(logging.Logger.manager.loggerDict)
    return GetLoggersResponse(
        [Logger(n, _level_name(logging.getLogger(n).getEffectiveLevel())) for n in names])

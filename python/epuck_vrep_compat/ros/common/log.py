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
MAX_NEW_LOGGERS = 1000  # loggers clients may create through ~set_logger_level (logging keeps
                        # every logger for the life of the process)


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


def serve_logger_services_safely(max_new_loggers: int = MAX_NEW_LOGGERS):
    """Make this node's ``~get_loggers`` answer every time and its ``~set_logger_level`` keep
    memory bounded.

    rospy's ``get_loggers`` iterates ``logging.Logger.manager.loggerDict`` while other threads
    may create loggers (rospy makes some per connection), and then fails with "dictionary
    changed size during iteration"; it also fails on a level it has no name for. rospy's
    ``set_logger_level`` creates a logger for any name a client sends, and logging keeps every
    logger for the life of the process, so a client naming new loggers without end grows the
    node without end. Call after ``rospy.init_node``: the registered services keep their names
    and types; ``get_loggers`` copies the logger table under logging's own lock first;
    ``set_logger_level`` sets a logger that exists as before, creates at most
    ``max_new_loggers`` new ones, and refuses a new name beyond that with a message saying so
    (the caller's service call fails)."""
    from rospy.impl.registration import get_service_manager
    handlers = {"~get_loggers": _get_loggers, "~set_logger_level": LoggerLevels(max_new_loggers)}
    for name, handler in handlers.items():
        service = get_service_manager().get_service(rospy.resolve_name(name))
        if service is not None:
            service.handler = handler


class LoggerLevels:
    """``~set_logger_level``'s handler: rospy's, but with at most ``max_new`` loggers created."""

    def __init__(self, max_new: int):
        self._max_new = max_new
        self._created = 0
        self._lock = threading.Lock()

    def __call__(self, request):
        from roscpp.srv import SetLoggerLevelResponse
        level = _LEVELS.get(request.level.upper())
        if level is None:                   # rospy's answer: a line in the log, no failure
            logging.getLogger("rospy").error("Bad logging level: %s", request.level.upper())
            return SetLoggerLevelResponse()
        with self._lock:
            if request.logger and request.logger not in logging.Logger.manager.loggerDict:
                if self._created >= self._max_new:
                    raise rospy.ServiceException(
                        f"no logger named {request.logger[:200]!r}, and {self._max_new} "
                        "loggers have been created through set_logger_level already: only "
                        "the levels of existing loggers can be set")
                self._created += 1
                if self._created == self._max_new:
                    rospy.logwarn("set_logger_level: %d loggers created through the service; "
                                  "new names are refused from now on", self._max_new)
            logging.getLogger(request.logger or None).setLevel(level)
        return SetLoggerLevelResponse()


_LEVEL_NAMES = ((logging.CRITICAL, "FATAL"), (logging.ERROR, "ERROR"),
                (logging.WARNING, "WARN"), (logging.INFO, "INFO"), (logging.DEBUG, "DEBUG"))


_LEVELS = {name: number for number, name in _LEVEL_NAMES}


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

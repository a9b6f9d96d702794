"""What a long run cannot grow (issue 27, the README's "Bounds"): the throttled log's keys,
the error log's entries and the signals a client sets. The stream tables' bound is in
test_vrep_streams_logic.py."""
import os

import pytest

from epuck_vrep_compat.ros.common import log
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim.control import RUNNING, SimulationControl
from epuck_vrep_compat.vrep import backend as vrep_backend
from epuck_vrep_compat.vrep.backend import (
    MAX_ERROR_CHARS, MAX_ERRORS, ErrorLog, VrepBackend, VrepError)
from repo import REPO

WORLDS = os.path.join(REPO, "test", "worlds")


@pytest.fixture
def clock(monkeypatch):
    """The log's wall clock, moved by hand; rospy's warnings counted."""
    now, lines = [100.0], []
    monkeypatch.setattr(log.time, "monotonic", lambda: now[0])
    monkeypatch.setattr(log.rospy, "logwarn", lambda fmt, *args: lines.append(fmt % args))
    return now, lines


def test_throttled_log_throttles_per_key(clock):
    now, lines = clock
    throttled = ThrottledLog(period_s=5.0)
    for _ in range(3):
        throttled.warn("a", "a %d", 1)
        throttled.warn("b", "b")
    assert lines == ["a 1", "b"]
    now[0] += 5.0
    throttled.warn("a", "a %d", 2)
    assert lines[-1] == "a 2"


def test_throttled_log_forgets_expired_keys_first(clock):
    now, lines = clock
    throttled = ThrottledLog(period_s=5.0, max_keys=10)
    for k in range(10):
        throttled.warn(f"old {k}", "x")
    now[0] += 6.0                       # every old key's period has passed
    throttled.warn("fresh", "x")
    throttled.warn("new", "x")
    assert len(throttled) == 2          # the expired ten went, not only the oldest one
    throttled.warn("fresh", "x")        # still throttled: it was kept
    assert len(lines) == 12


def test_throttled_log_keeps_at_most_max_keys_under_a_flood(clock):
    now, lines = clock
    throttled = ThrottledLog(period_s=5.0, max_keys=100)
    for k in range(10_000):             # distinct keys (a client's names), all within a period
        throttled.warn(f"topic {k}", "x")
    assert len(throttled) == 100
    throttled.warn("topic 9999", "x")   # the newest are the ones kept: still throttled
    assert len(lines) == 10_000
    assert log.MAX_KEYS == 1000


def test_error_log_keeps_the_last_entries_each_cut():
    errors = ErrorLog()
    for k in range(MAX_ERRORS + 20):
        errors.add(f"error {k}")
    errors.add("x" * (10 * MAX_ERROR_CHARS))
    kept = errors.take()
    assert len(kept) == MAX_ERRORS
    assert kept[0] == "error 21" and kept[-2] == f"error {MAX_ERRORS + 19}"
    assert len(kept[-1]) == MAX_ERROR_CHARS and kept[-1].endswith("...")
    assert errors.take() == []
    errors.add("y" * MAX_ERROR_CHARS)   # at the bound: kept whole
    assert errors.take() == ["y" * MAX_ERROR_CHARS]


def test_signals_set_through_vrep_are_at_most_max_signals_names_per_kind(monkeypatch):
    monkeypatch.setattr(vrep_backend, "MAX_SIGNALS", 5)
    sim = build_simulation(load_scene(os.path.join(WORLDS, "wall.yaml")),
                           SimulationConfig(["ePuck0"], seed=1))
    backend = VrepBackend(sim, SimulationControl(sim, RUNNING), real_time=False)
    for k in range(5):
        backend.set_signal("int", f"s{k}", k)
    with pytest.raises(VrepError, match="5 int signals exist"):
        backend.set_signal("int", "one more", 1)
    backend.set_signal("int", "s4", 44)            # a name that exists: still set
    backend.set_signal("float", "f", 1.0)          # each kind has its own table
    assert backend.signal("int", "s4") == 44 and len(backend.signals["int"]) == 5
    backend.clear_signal("int", "s0")
    backend.set_signal("int", "one more", 1)       # room again once one is cleared
    assert vrep_backend.MAX_SIGNALS == 5 and backend.signal("int", "one more") == 1


def test_the_signal_bound_is_ten_thousand():
    assert vrep_backend.MAX_SIGNALS == 10_000


def test_set_logger_level_creates_at_most_max_new_loggers():
    import logging
    import uuid

    import rospy
    from roscpp.srv import SetLoggerLevelRequest
    prefix = f"bounds_test_{uuid.uuid4().hex}"
    levels = log.LoggerLevels(max_new=3)
    logging.getLogger(f"{prefix}.existing")
    for k in range(3):
        levels(SetLoggerLevelRequest(logger=f"{prefix}.new{k}", level="warn"))
        assert logging.getLogger(f"{prefix}.new{k}").level == logging.WARNING
    with pytest.raises(rospy.ServiceException, match="3 loggers have been created"):
        levels(SetLoggerLevelRequest(logger=f"{prefix}.one_more", level="debug"))
    assert f"{prefix}.one_more" not in logging.Logger.manager.loggerDict
    levels(SetLoggerLevelRequest(logger=f"{prefix}.existing", level="error"))   # still set
    levels(SetLoggerLevelRequest(logger=f"{prefix}.new1", level="FATAL"))
    assert logging.getLogger(f"{prefix}.existing").level == logging.ERROR
    assert logging.getLogger(f"{prefix}.new1").level == logging.CRITICAL
    levels(SetLoggerLevelRequest(logger=f"{prefix}.other", level="loud"))   # as rospy: no error
    assert f"{prefix}.other" not in logging.Logger.manager.loggerDict


def test_the_new_logger_bound_is_a_thousand():
    assert log.MAX_NEW_LOGGERS == 1000

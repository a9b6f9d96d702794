"""The speed scale's watchdog on the real cell (no master): a watched robot whose supervisor
falls silent for longer than the timeout, in simulated time, stops and holds; a fresh scale
resumes it; robots not watched, or a watchdog turned off, never stop; a reset restarts the
clocks; bad configurations are refused and change nothing."""
import os

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import build_simulation
from epuck_vrep_compat.scene.scene_file import load_scene
from repo import REPO

TIMEOUT_S = 0.25                       # 5 steps of 50 ms


@pytest.fixture
def sim():
    sim = build_simulation(load_scene(os.path.join(REPO, "worlds", "merlin_cell.yaml")))
    yield sim
    sim.cell.close()


def steps(sim, n, feed=None):
    """n steps; before each, ``feed()`` (a supervisor answering every step)."""
    for _ in range(n):
        if feed is not None:
            feed()
        sim.step()


def joints(sim, robot):
    return np.array(sim.cell.arm_by_name[robot].q, dtype=float)


def test_off_by_default_nobody_stops(sim):
    steps(sim, 20)
    assert all(arm.speed_scale == 1.0 for arm in sim.cell.arms)
    assert not any(sim.cell.watchdog.stopped.values())


def test_a_silent_supervisor_stops_the_watched_robot_after_the_timeout(sim):
    sim.cell.commands.watch_speed_scale(TIMEOUT_S, ["IRB140"])
    feed = lambda: sim.cell.commands.speed_scale("IRB140", 0.5)   # noqa: E731
    start = joints(sim, "IRB140")
    steps(sim, 20, feed)                         # answered every step: never stopped
    assert np.abs(joints(sim, "IRB140") - start).max() > 0.01     # its script moves it
    irb = sim.cell.arm_by_name["IRB140"]
    assert irb.speed_scale == 0.5 and not sim.cell.watchdog.stopped["IRB140"]
    # the last scale came before the 20th step: 4 silent steps later it is 5 steps = 0.25 s
    # old, the timeout: still on; one more and it is past it: a protective stop
    steps(sim, 4)
    assert irb.speed_scale == 0.5
    steps(sim, 1)
    assert irb.speed_scale == 0.0 and sim.cell.watchdog.stopped["IRB140"]
    held = joints(sim, "IRB140")
    steps(sim, 10)
    np.testing.assert_allclose(joints(sim, "IRB140"), held, atol=1e-3)
    # the robots not watched go on at their own scale
    assert sim.cell.arm_by_name["SIX"].speed_scale == 1.0
    assert "SIX" not in sim.cell.watchdog.stopped
    # a fresh scale resumes it, as it is
    sim.cell.commands.speed_scale("IRB140", 0.8)
    steps(sim, 1)
    assert irb.speed_scale == 0.8 and not sim.cell.watchdog.stopped["IRB140"]


def test_the_first_scale_must_come_within_the_timeout_and_reset_restarts_the_clock(sim):
    sim.cell.commands.watch_speed_scale(TIMEOUT_S)          # None: every robot
    steps(sim, 6)
    assert all(sim.cell.watchdog.stopped[arm.spec.name] for arm in sim.cell.arms)
    assert all(arm.speed_scale == 0.0 for arm in sim.cell.arms)
    sim.reset()
    assert not any(sim.cell.watchdog.stopped.values())
    steps(sim, 5)
    assert not any(sim.cell.watchdog.stopped.values())


def test_turned_off_it_stops_nobody(sim):
    sim.cell.commands.watch_speed_scale(TIMEOUT_S, ["IRB140"])
    sim.cell.commands.watch_speed_scale(0.0)
    steps(sim, 20)
    assert sim.cell.arm_by_name["IRB140"].speed_scale == 1.0


@pytest.mark.parametrize("timeout, robots, match", [
    (-1.0, None, ">= 0"), (float("nan"), None, ">= 0"), (0.25, ["NoSuchRobot"], "NoSuchRobot")])
def test_bad_configurations_are_refused_and_change_nothing(sim, timeout, robots, match):
    sim.cell.commands.watch_speed_scale(TIMEOUT_S, ["IRB140"])
    with pytest.raises(ValueError, match=match):
        sim.cell.commands.watch_speed_scale(timeout, robots)
    assert sim.cell.watchdog.timeout_s == TIMEOUT_S
    assert sim.cell.watchdog.watches("IRB140") and not sim.cell.watchdog.watches("SIX")

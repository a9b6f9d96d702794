"""The youBot's base driven as V-REP drives it: a client's wheel-joint velocities move the base
through the mecanum kinematics (no master); a twist command takes the base back."""
import math
import os

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import build_simulation
from epuck_vrep_compat.cell.devices.mecanum import (
    WHEEL_LX_PLUS_LY_M, WHEEL_RADIUS_M, WHEELS, body_twist, wheel_speeds)
from epuck_vrep_compat.scene.scene_file import load_scene
from repo import REPO


@pytest.fixture
def sim():
    simulation = build_simulation(load_scene(os.path.join(REPO, "worlds", "merlin_cell.yaml")))
    yield simulation
    simulation.cell.close()


@pytest.mark.parametrize("twist", [(0.2, 0.0, 0.0), (0.0, -0.15, 0.0), (0.0, 0.0, 0.7),
                                   (0.1, 0.05, -0.3)])
def test_wheel_speeds_and_body_twist_invert_each_other(twist):
    np.testing.assert_allclose(body_twist(wheel_speeds(*twist)), twist, atol=1e-12)


def test_the_rollers_pair_the_wheels_as_a_mecanum_base():
    # forward: all wheels alike; sideways left: fl and rr backwards; turning left: left side back
    assert len(set(wheel_speeds(0.1, 0.0, 0.0).values())) == 1
    left = wheel_speeds(0.0, 0.1, 0.0)
    assert left["fl"] < 0 < left["rl"] and left["rr"] < 0 < left["fr"]
    turn = wheel_speeds(0.0, 0.0, 0.5)
    assert turn["fl"] < 0 and turn["rl"] < 0 and turn["rr"] > 0 and turn["fr"] > 0
    assert turn["fr"] == pytest.approx(0.5 * WHEEL_LX_PLUS_LY_M / WHEEL_RADIUS_M)


def drive_wheels(sim, omega, seconds):
    """Commands each rollingJoint's velocity through its joint component (the object
    simRosSetJointTargetVelocity reaches) and steps; returns the base's (x, y, yaw) before and
    after, and the time stepped."""
    bot = sim.cell.arm_by_name["youBot"]
    for w in WHEELS:
        joint = sim.registry.get(sim.registry.handle_of(f"rollingJoint_{w}"))
        joint.properties["joint"].set_target_velocity(omega[w])
    before = bot.base_xy_yaw.copy()
    steps = int(round(seconds / sim.step_s))
    for _ in range(steps):
        sim.step()
    return before, bot.base_xy_yaw.copy(), steps * sim.step_s


def body_motion(before, after):
    """(forward, left, turned) of the base between two (x, y, yaw), in the first's frame."""
    dx, dy = after[0] - before[0], after[1] - before[1]
    c, s = math.cos(before[2]), math.sin(before[2])
    turned = math.atan2(math.sin(after[2] - before[2]), math.cos(after[2] - before[2]))
    return c * dx + s * dy, -s * dx + c * dy, turned


@pytest.mark.parametrize("twist", [(0.2, 0.0, 0.0), (0.0, 0.15, 0.0), (0.0, -0.1, 0.0)])
def test_wheels_drive_the_base_forward_and_sideways(sim, twist):
    before, after, t = drive_wheels(sim, wheel_speeds(*twist), 2.0)
    forward, left, turned = body_motion(before, after)
    assert forward == pytest.approx(twist[0] * t, abs=1e-9)
    assert left == pytest.approx(twist[1] * t, abs=1e-9)
    assert turned == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(sim.cell.arm_by_name["youBot"].twist, twist, atol=1e-12)


def test_wheels_turn_the_base_in_place(sim):
    before, after, t = drive_wheels(sim, wheel_speeds(0.0, 0.0, 0.5), 2.0)
    forward, left, turned = body_motion(before, after)
    assert turned == pytest.approx(0.5 * t, abs=1e-9)
    assert math.hypot(forward, left) < 1e-9


def test_the_script_stops_and_a_twist_takes_the_base_back(sim):
    bot = sim.cell.arm_by_name["youBot"]
    drive_wheels(sim, {w: 0.0 for w in WHEELS}, 1.0)
    assert bot.external and bot.wheel_driven
    np.testing.assert_allclose(bot.twist, 0.0)            # wheels stopped: the base stands
    bot.set_twist(0.1, 0.0, 0.0)
    assert not bot.wheel_driven
    sim.step()
    k = bot.wheels["fl"]
    assert bot.target[k] == pytest.approx(0.1 / WHEEL_RADIUS_M)
    sim.reset()
    assert not bot.wheel_driven and not bot.external

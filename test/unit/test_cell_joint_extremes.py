"""Extreme joint values on the cell keep its physics finite (no master): bench/fuzz_memory.py's
third round put a youBot wheel (a cyclic joint) at 1e308 rad and then drove it by velocity;
pybullet turned the whole youBot into NaN and every later step failed (``poses[18]``, its
first arm link). A cyclic joint's angle is now taken modulo a turn and its target the shortest
way; a stop gives every joint its URDF force back; an arm whose physics diverges anyway is put
back to its state before the step, which reports it once, and the next steps go on."""
import math

import numpy as np
import pytest

WHEEL = "rollingJoint_fl"


@pytest.fixture
def cell(backend_of):
    return backend_of("merlin_cell.yaml")


def youbot_finite(backend):
    arm = backend.sim.cell.arm_by_name["youBot"]
    return all(np.all(np.isfinite(a)) for a in (arm.q, arm.qd, arm.link_position,
                                                 arm.link_quat, arm.base_xy_yaw))


@pytest.mark.parametrize("position", [1e308, -1e308, 2e6, 7.0])
def test_a_wheel_set_far_then_driven_keeps_the_cell_finite(cell, position):
    wheel = cell.sim.registry.handle_of(WHEEL)
    cell.joint_command(wheel, "position", position)
    angle, _, _ = cell.joint_state(wheel)
    assert -math.pi < angle <= math.pi
    assert angle == pytest.approx(math.remainder(position, 2.0 * math.pi), abs=1e-9)
    for _ in range(3):
        cell.sim.step()
    cell.joint_command(wheel, "target_velocity", 1.0)
    for _ in range(20):
        cell.sim.step()                     # raised ValueError: poses[18] before the fix
    assert youbot_finite(cell)


def test_a_cyclic_target_is_reached_the_shortest_way(cell):
    wheel = cell.sim.registry.handle_of(WHEEL)
    arm = cell.sim.cell.arm_by_name["youBot"]
    k = arm.movable_index(WHEEL)
    cell.joint_command(wheel, "target_position", 1e308)
    assert abs(arm.target[k] - arm.q[k]) <= math.pi
    cell.joint_command(wheel, "target_position", 2.0 * math.pi + 0.25)
    assert arm.target[k] == pytest.approx(arm.q[k] + math.remainder(0.25 - arm.q[k],
                                                                     2.0 * math.pi))
    for _ in range(10):
        cell.sim.step()
    assert youbot_finite(cell)


def test_a_stop_gives_the_joints_their_forces_back(cell):
    wheel = cell.sim.registry.handle_of(WHEEL)
    joint = cell.sim.registry.get(wheel).properties["joint"]
    rated = joint.max_force
    cell.joint_command(wheel, "force", 1e308)
    assert joint.max_force == 1e308
    cell.sim.reset()                        # what simRosStopSimulation does to the scene
    assert joint.max_force == rated


def test_an_arm_that_diverges_is_put_back_and_the_steps_go_on(cell):
    """The old defect's state forced past the joint's checks: the step that diverges says so
    once; the arm is where it was, at rest; later steps, a stop and a start work."""
    arm = cell.sim.cell.arm_by_name["youBot"]
    k = arm.movable_index(WHEEL)
    arm.reset_joint(k, 1e308)               # what simRosSetJointPosition stored before the fix
    cell.sim.step()
    base = arm.base_xy_yaw.copy()
    arm.joints[k].set_target_velocity(1.0)
    with pytest.raises(ValueError, match="youBot diverged"):
        cell.sim.step()
    assert youbot_finite(cell)
    np.testing.assert_allclose(arm.base_xy_yaw, base)
    assert np.all(arm.qd == 0.0)
    for _ in range(10):
        cell.sim.step()
    assert youbot_finite(cell)
    cell.sim.reset()
    cell.sim.step()
    assert youbot_finite(cell)

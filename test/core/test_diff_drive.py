"""Differential drive: exact arcs, clamping that keeps curvature, NaN commands, slip."""
import math

import numpy as np

R, L = 0.02, 0.053
DT = 0.05


def drive(swarm, left, right, steps):
    command = np.array([[left, right]] * swarm.size, float)
    for _ in range(steps):
        swarm.step(DT, command)


def test_straight_line(make_swarm):
    swarm = make_swarm()
    drive(swarm, 3.0, 3.0, 100)
    x, y, yaw = swarm.poses[0]
    assert abs(x - R * 3.0 * 100 * DT) < 1e-9 and abs(y) < 1e-9 and yaw == 0.0
    assert np.allclose(swarm.wheel_angles[0], 3.0 * 100 * DT)


def test_arc_matches_the_unicycle_formula(make_swarm):
    x0, y0, yaw0 = 0.1, -0.2, 0.3
    swarm = make_swarm([(100, x0, y0, yaw0)])
    drive(swarm, 2.0, 4.0, 137)
    v, w = R * 3.0, R * 2.0 / L
    t = 137 * DT
    x = x0 + v / w * (math.sin(yaw0 + w * t) - math.sin(yaw0))
    y = y0 - v / w * (math.cos(yaw0 + w * t) - math.cos(yaw0))
    yaw = math.remainder(yaw0 + w * t, 2 * math.pi)
    pose = swarm.poses[0]
    assert abs(pose[0] - x) < 1e-9 and abs(pose[1] - y) < 1e-9
    assert abs(math.remainder(pose[2] - yaw, 2 * math.pi)) < 1e-9
    assert np.allclose(swarm.velocities[0, 2], w)
    # No slip: odometry is ground truth, with the commanded twist.
    assert np.allclose(swarm.odometry[0], [*pose, v, w], atol=1e-12)


def test_commands_above_the_limit_keep_curvature(make_swarm):
    swarm = make_swarm()
    drive(swarm, 10.0, 5.0, 1)
    left, right = swarm.wheel_speeds[0]
    assert math.isclose(left, 6.283185307)
    assert math.isclose(right / left, 0.5)


def test_nan_commands_stop_the_wheels(make_swarm):
    swarm = make_swarm()
    drive(swarm, 2.0, 2.0, 5)
    before = swarm.poses.copy()
    drive(swarm, math.nan, 2.0, 5)
    drive(swarm, math.inf, -math.inf, 5)
    assert np.array_equal(swarm.poses, before) and not swarm.wheel_speeds.any()
    for state in (swarm.velocities, swarm.odometry, swarm.accel, swarm.wheel_angles):
        assert np.isfinite(state).all()


def test_slip_makes_odometry_drift_from_ground_truth(make_swarm):
    swarm = make_swarm([(100, 0, 0, 0), (101, 1, 0, 0)])
    swarm.set_slip_noise(np.array([0.1, 0.0]))
    drive(swarm, 4.0, 4.0, 100)
    drift = np.linalg.norm(swarm.odometry[:, :2] - swarm.poses[:, :2], axis=1)
    assert drift[0] > 1e-4 and drift[1] == 0.0
    assert abs(swarm.wheel_speeds[0, 0] - 4.0) > 0.0


def test_set_pose_and_set_odometry(make_swarm):
    swarm = make_swarm()
    swarm.set_pose(0, 0.5, 0.5, 4.0)
    swarm.set_odometry(0, 1.0, 2.0, 0.25)
    assert np.allclose(swarm.poses[0], [0.5, 0.5, 4.0 - 2 * math.pi])
    assert np.allclose(swarm.odometry[0, :3], [1.0, 2.0, 0.25])

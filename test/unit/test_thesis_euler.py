"""V-REP's Euler angles of a quaternion (R = Rx(alpha) Ry(beta) Rz(gamma)), the orientation
convention of the thesis's /<Robot>_PosOrAss and _PosOrRel, against known rotations."""
import math

import numpy as np
import pytest

from epuck_vrep_compat.geometry.transforms import quat_from_axis_angle, quat_mul, vrep_euler_angles


def rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def quat_of_vrep_euler(alpha, beta, gamma):
    """Rx(alpha) Ry(beta) Rz(gamma) as a quaternion (x, y, z, w)."""
    return quat_mul(quat_mul(quat_from_axis_angle((1, 0, 0), alpha),
                             quat_from_axis_angle((0, 1, 0), beta)),
                    quat_from_axis_angle((0, 0, 1), gamma))


@pytest.mark.parametrize("quat, euler", [
    ((0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0)),
    ((math.sin(0.15), 0.0, 0.0, math.cos(0.15)), (0.3, 0.0, 0.0)),             # Rx(0.3)
    ((0.0, math.sin(0.2), 0.0, math.cos(0.2)), (0.0, 0.4, 0.0)),               # Ry(0.4)
    ((0.0, 0.0, math.sin(-0.6), math.cos(-0.6)), (0.0, 0.0, -1.2)),            # Rz(-1.2)
    ((0.0, 0.0, 1.0, 0.0), (0.0, 0.0, math.pi)),                               # Rz(pi)
    ((math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)), (math.pi / 2, 0.0, 0.0)),     # Rx(90 deg)
])
def test_single_axis_rotations(quat, euler):
    difference = np.subtract(vrep_euler_angles(quat), euler)
    np.testing.assert_allclose(np.angle(np.exp(1j * difference)), 0.0, atol=1e-12)  # pi = -pi


def test_the_order_is_x_then_y_then_z_in_moving_axes():
    alpha, beta, gamma = 0.3, -0.4, 1.2
    q = quat_of_vrep_euler(alpha, beta, gamma)
    np.testing.assert_allclose(matrix(q), rx(alpha) @ ry(beta) @ rz(gamma), atol=1e-12)
    np.testing.assert_allclose(vrep_euler_angles(q), [alpha, beta, gamma], atol=1e-12)
    # not the ROS roll-pitch-yaw convention, Rz Ry Rx:
    assert not np.allclose(matrix(q), rz(gamma) @ ry(beta) @ rx(alpha), atol=1e-3)


def test_the_theses_joint_orientations_round_trip():
    for euler in [(1.5707, 1.3294, 1.5708), (1.5707, -0.9197, 1.5707),
                  (1.0853e-06, -5.9005e-07, 2.9802e-07)]:        # thesis figures 5.3 and 5.4
        np.testing.assert_allclose(vrep_euler_angles(quat_of_vrep_euler(*euler)), euler,
                                   atol=1e-9)


def test_any_rotation_rebuilds_from_its_angles_and_q_equals_minus_q():
    rng = np.random.default_rng(20240611)
    for q in rng.normal(size=(200, 4)):
        q /= np.linalg.norm(q)
        alpha, beta, gamma = vrep_euler_angles(q)
        assert -math.pi / 2 <= beta <= math.pi / 2
        np.testing.assert_allclose(rx(alpha) @ ry(beta) @ rz(gamma), matrix(q), atol=1e-9)
        np.testing.assert_allclose(vrep_euler_angles(-q), [alpha, beta, gamma], atol=1e-9)


@pytest.mark.parametrize("beta", [math.pi / 2, -math.pi / 2])
def test_gimbal_lock_keeps_the_rotation(beta):
    q = quat_of_vrep_euler(0.3, beta, 0.5)
    alpha2, beta2, gamma2 = vrep_euler_angles(q)
    assert beta2 == pytest.approx(beta) and gamma2 == 0.0
    np.testing.assert_allclose(rx(alpha2) @ ry(beta2) @ rz(gamma2), matrix(q), atol=1e-9)

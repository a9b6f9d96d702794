"""The e-puck2's time-of-flight sensor (TofSensorArray): distance along the pitched axis
against a wall at known distances, range limits, its own seeded noise per robot."""
import math

import numpy as np
import pytest

from conftest import GREY, IDENTITY

from epuck_vrep_compat import _core
PITCH = -0.21
MOUNT = (0.035, 0.0, 0.034)


def wall_world(face_x):
    """A tall wall whose face is the plane x = face_x."""
    world = _core.CollisionWorld()
    world.add_box(100, (0.01, 2.0, 1.0), (face_x + 0.01, 0.0, 0.5), IDENTITY, GREY)
    return world


def robot(world, handle=1, x=0.0, y=0.0):
    world.add_cylinder(handle, 0.037, 0.05, (x, y, 0.025), IDENTITY, GREY, _core.GROUP_ROBOT)


@pytest.mark.parametrize("face_x", [0.1, 0.3, 0.6, 1.2])
def test_a_wall_reads_its_distance_along_the_pitched_axis(face_x):
    world = wall_world(face_x)
    robot(world)
    tof = _core.TofSensorArray(np.array(MOUNT), PITCH)
    reading = tof.read(world, np.zeros((1, 3)), [1], [0], noise=False)
    expected = (face_x - MOUNT[0]) / math.cos(PITCH)
    assert reading[0] == pytest.approx(expected, abs=1e-9)


def test_turned_robots_and_range_limits():
    world = wall_world(0.5)
    robot(world, 1)
    robot(world, 2, y=0.3)
    robot(world, 3, y=-0.3)
    poses = np.array([[0.0, 0.0, math.pi],           # facing away: nothing within 2 m
                      [0.5 - 0.035 - 0.002, 0.3, 0.0],  # 2 mm from the wall: clamped up to 5 mm
                      [0.0, -0.3, math.pi / 3]])     # 60 degrees off the wall's normal
    tof = _core.TofSensorArray(np.array(MOUNT), PITCH)
    r = tof.read(world, poses, [1, 2, 3], [0, 1, 2], noise=False)
    assert r[0] == 2.0
    assert r[1] == pytest.approx(0.005)
    origin_x = 0.035 * math.cos(math.pi / 3)
    assert r[2] == pytest.approx((0.5 - origin_x) / (math.cos(PITCH) * math.cos(math.pi / 3)),
                                 abs=1e-9)


def test_noise_is_seeded_per_robot_and_has_the_configured_spread():
    world = wall_world(0.5)
    robot(world, 1)
    robot(world, 2, y=0.5)
    poses = np.array([[0.0, 0.0, 0.0], [0.0, 0.5, 0.0]])
    d = 0.465 / math.cos(PITCH)

    def run(seed, ids, steps=4000):
        tof = _core.TofSensorArray(np.array(MOUNT), PITCH, stddev_m=0.003, stddev_rel=0.02,
                                   seed=seed)
        return np.array([tof.read(world, poses, [1, 2], ids) for _ in range(steps)])

    a = run(7, [0, 1])
    assert np.array_equal(a, run(7, [0, 1]))                  # same seed, same run
    assert not np.array_equal(a, run(8, [0, 1]))              # another seed, other noise
    swapped = run(7, [1, 0])                                  # the stream follows the id
    assert np.array_equal(a[:, 0], swapped[:, 1])
    sd = 0.003 + 0.02 * d
    n = a.shape[0]
    assert abs(a[:, 0].mean() - d) < 3 * sd / math.sqrt(n)
    assert abs(a[:, 0].std() - sd) < 3 * sd / math.sqrt(2 * n)


def test_reseed_restarts_and_bad_specs_are_refused():
    world = wall_world(0.5)
    robot(world)
    tof = _core.TofSensorArray(seed=3)
    first = [tof.read(world, np.zeros((1, 3)), [1], [0])[0] for _ in range(5)]
    tof.reseed(3)
    assert [tof.read(world, np.zeros((1, 3)), [1], [0])[0] for _ in range(5)] == first
    with pytest.raises(ValueError):
        _core.TofSensorArray(min_range_m=3.0, max_range_m=2.0)
    with pytest.raises(ValueError):
        _core.TofSensorArray(stddev_m=-1.0)
    with pytest.raises(ValueError):
        tof.read(world, np.zeros((2, 3)), [1], [0])
    with pytest.raises(ValueError):
        tof.read(world, np.full((1, 3), np.nan), [1], [0])

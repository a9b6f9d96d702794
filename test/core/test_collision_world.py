"""CollisionWorld: objects keyed by handles, their poses and colours, and bad arguments."""
import math

import numpy as np
import pytest
from conftest import GREY, IDENTITY, yaw_quaternion

from epuck_vrep_compat import _core


def test_groups_are_single_bits():
    assert (_core.GROUP_STATIC, _core.GROUP_ROBOT, _core.GROUP_FLOOR, _core.GROUP_DYNAMIC,
            _core.GROUP_ALL) == (1, 2, 4, 8, 15)


def test_add_query_move_and_remove(world):
    world.add_box(3, (0.1, 0.2, 0.3), (1, 2, 3), IDENTITY, (1, 0, 0))
    world.add_cylinder(1, 0.05, 0.1, (0, 0, 0.05), IDENTITY, GREY, _core.GROUP_DYNAMIC)
    world.add_sphere(2, 0.02, (0, 1, 0.02), IDENTITY, GREY)
    assert world.handles() == [1, 2, 3] and world.has(2) and not world.has(4)
    position, quaternion = world.get_pose(3)
    assert np.allclose(position, (1, 2, 3)) and np.allclose(quaternion, IDENTITY)
    world.set_pose(3, (4, 5, 6), yaw_quaternion(math.pi / 2))
    position, quaternion = world.get_pose(3)
    assert np.allclose(position, (4, 5, 6))
    assert np.allclose(np.abs(quaternion), np.abs(yaw_quaternion(math.pi / 2)))
    world.set_color(3, (0, 1, 0))
    world.set_background((0.1, 0.2, 0.3))
    world.remove(3)
    assert world.handles() == [1, 2]


def test_quaternions_are_normalised(world):
    world.add_box(1, (0.1, 0.1, 0.1), (0, 0, 0), (0, 0, 2, 2), GREY)
    _, quaternion = world.get_pose(1)
    assert math.isclose(np.linalg.norm(quaternion), 1.0)


def test_unknown_handles_raise_key_error(world):
    for call in (lambda: world.get_pose(9), lambda: world.remove(9),
                 lambda: world.set_pose(9, (0, 0, 0), IDENTITY),
                 lambda: world.set_color(9, GREY)):
        with pytest.raises(KeyError):
            call()


@pytest.mark.parametrize(
    "kwargs",
    [dict(handle=-1), dict(half_extents=(0.1, 0.0, 0.1)), dict(position=(0, math.nan, 0)),
     dict(position=(0, 0)), dict(quaternion=(0, 0, 0, 0)), dict(quaternion=(0, 0, math.inf, 1)),
     dict(rgb=(1.5, 0, 0)), dict(group=3), dict(group=0)],
)
def test_bad_arguments_raise_value_error(world, kwargs):
    arguments = dict(handle=1, half_extents=(0.1, 0.1, 0.1), position=(0, 0, 0),
                     quaternion=IDENTITY, rgb=GREY, group=_core.GROUP_STATIC)
    arguments.update(kwargs)
    with pytest.raises(ValueError):
        world.add_box(**arguments)
    assert world.handles() == []


def test_duplicate_handle_raises_value_error(world):
    world.add_sphere(1, 0.1, (0, 0, 0), IDENTITY, GREY)
    with pytest.raises(ValueError):
        world.add_box(1, (0.1, 0.1, 0.1), (1, 0, 0), IDENTITY, GREY)
    with pytest.raises(ValueError):
        world.add_cylinder(2, -0.1, 0.1, (1, 0, 0), IDENTITY, GREY)

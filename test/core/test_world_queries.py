"""CollisionWorld.ray_cast: exact hits on boxes, cylinders and spheres; masks and ignores."""
import math

import numpy as np
import pytest
from conftest import GREY, IDENTITY, yaw_quaternion

from epuck_vrep_compat import _core


def cast(world, origin, direction, max_distance=10.0, **kwargs):
    distance, handle, normal = world.ray_cast(np.array([origin], float),
                                              np.array([direction], float), max_distance,
                                              **kwargs)
    return distance[0], handle[0], normal[0]


def test_box_face_distance_and_normal(world):
    world.add_box(7, (0.01, 0.5, 0.5), (0.31, 0, 0), IDENTITY, GREY)
    distance, handle, normal = cast(world, (0, 0.1, 0.2), (2, 0, 0))  # normalised internally
    assert distance == pytest.approx(0.3, abs=1e-12) and handle == 7
    assert np.allclose(normal, (-1, 0, 0))
    slanted = math.radians(30)
    distance, _, _ = cast(world, (0, 0, 0), (math.cos(slanted), math.sin(slanted), 0))
    assert distance == pytest.approx(0.3 / math.cos(slanted), abs=1e-12)


def test_rotated_box(world):
    # A cube turned by 45 degrees: its corner points at the ray.
    world.add_box(1, (0.1, 0.1, 0.1), (1, 0, 0), yaw_quaternion(math.pi / 4), GREY)
    distance, _, _ = cast(world, (0, 0, 0), (1, 0, 0))
    assert distance == pytest.approx(1 - 0.1 * math.sqrt(2), abs=1e-12)


def test_cylinder_side_and_cap(world):
    world.add_cylinder(2, 0.05, 0.2, (1, 0, 0.1), IDENTITY, GREY)
    distance, handle, normal = cast(world, (0, 0.03, 0.1), (1, 0, 0))
    assert distance == pytest.approx(1 - math.sqrt(0.05**2 - 0.03**2), abs=1e-12)
    assert handle == 2 and normal[2] == 0 and normal[0] < 0
    distance, _, normal = cast(world, (1.01, 0, 1), (0, 0, -1))
    assert distance == pytest.approx(0.8, abs=1e-12) and np.allclose(normal, (0, 0, 1))


def test_sphere(world):
    world.add_sphere(3, 0.1, (0, 0, 1), IDENTITY, GREY)
    distance, handle, normal = cast(world, (0, 0, 0), (0, 0, 1))
    assert distance == pytest.approx(0.9, abs=1e-12) and handle == 3
    assert np.allclose(normal, (0, 0, -1))


def test_closest_of_several_ignore_and_mask(world):
    world.add_box(1, (0.01, 1, 1), (0.5, 0, 0), IDENTITY, GREY, _core.GROUP_ROBOT)
    world.add_box(2, (0.01, 1, 1), (1.0, 0, 0), IDENTITY, GREY, _core.GROUP_STATIC)
    assert cast(world, (0, 0, 0), (1, 0, 0))[1] == 1
    assert cast(world, (0, 0, 0), (1, 0, 0), ignore_handle=1)[1] == 2
    assert cast(world, (0, 0, 0), (1, 0, 0), mask=_core.GROUP_STATIC)[1] == 2
    distance, handle, normal = cast(world, (0, 0, 0), (1, 0, 0), mask=_core.GROUP_FLOOR)
    assert distance == math.inf and handle == -1 and not normal.any()


def test_max_distance_and_start_inside(world):
    world.add_box(1, (0.1, 0.1, 0.1), (1, 0, 0), IDENTITY, GREY)
    distance, handle, _ = cast(world, (0, 0, 0), (1, 0, 0), max_distance=0.5)
    assert distance == math.inf and handle == -1
    distance, handle, _ = cast(world, (1, 0, 0), (0, 1, 0))
    assert distance == 0.0 and handle == 1


def test_batch_shapes_and_dtypes(world):
    world.add_sphere(1, 0.1, (1, 0, 0), IDENTITY, GREY)
    origins = np.zeros((4, 3))
    directions = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [1, 0.01, 0]])
    distance, handle, normal = world.ray_cast(origins, directions, 5.0)
    assert distance.shape == (4,) and handle.shape == (4,) and normal.shape == (4, 3)
    assert handle.dtype == np.int32
    assert list(handle) == [1, -1, -1, 1]


@pytest.mark.parametrize(
    "origins, directions",
    [(np.zeros((2, 2)), np.ones((2, 3))), (np.zeros((2, 3)), np.ones((3, 3))),
     (np.zeros((1, 3)), np.zeros((1, 3))), (np.full((1, 3), np.nan), np.ones((1, 3)))],
)
def test_bad_rays_raise_value_error(world, origins, directions):
    with pytest.raises(ValueError):
        world.ray_cast(origins, directions, 1.0)

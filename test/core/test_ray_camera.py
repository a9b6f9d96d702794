"""CollisionWorld.render: a ray-cast pinhole camera, REP 103 body frame, row 0 at the top."""
import math

import numpy as np
import pytest
from conftest import IDENTITY, yaw_quaternion

from epuck_vrep_compat import _core

W, H, FOV = 160, 120, math.radians(60)
CAMERA = (0.0, 0.0, 0.25)


def render(world, quaternion=IDENTITY, **kwargs):
    arguments = dict(near_m=0.01, far_m=5.0)
    arguments.update(kwargs)
    return world.render(CAMERA, quaternion, W, H, FOV, **arguments)


def red_wall(world, handle=1):
    """A 0.5 m square red wall facing the camera 1 m ahead, centred on the optical axis."""
    world.add_box(handle, (0.005, 0.25, 0.25), (1.005, 0.0, 0.25), IDENTITY, (1, 0, 0))


def test_wall_fills_the_expected_pixels_at_the_right_depth(world):
    red_wall(world)
    rgb, depth = render(world)
    assert rgb.shape == (H, W, 3) and rgb.dtype == np.uint8
    assert depth.shape == (H, W) and depth.dtype == np.float32
    # f = (H/2) / tan(FOV/2) = 103.9 px; the wall spans ±0.25 / 1.0 * f = ±25.98 px.
    expected = np.zeros((H, W), bool)
    expected[34:86, 54:106] = True
    red = (rgb[..., 0] > 0) & (rgb[..., 1] == 0) & (rgb[..., 2] == 0)
    assert np.array_equal(red, expected)
    assert np.all(np.abs(depth[expected] - 1.0) < 1e-6)  # along the axis, even at the edges
    assert np.all(depth[~expected] == 5.0)


def test_rows_run_top_down_and_columns_left_to_right(world):
    world.add_sphere(1, 0.03, (0.9, 0.0, 0.45), IDENTITY, (0, 1, 0))   # high
    world.add_sphere(2, 0.03, (0.9, 0.2, 0.25), IDENTITY, (0, 0, 1))   # to the left
    rgb, _ = render(world)
    green_rows, _ = np.nonzero(rgb[..., 1] > rgb[..., 0] + 50)
    _, blue_cols = np.nonzero(rgb[..., 2] > rgb[..., 0] + 50)
    assert green_rows.size and green_rows.max() < H // 2
    assert blue_cols.size and blue_cols.max() < W // 2


def test_orientation_ignore_and_background(world):
    world.add_box(1, (0.25, 0.005, 0.25), (0.0, 1.005, 0.25), IDENTITY, (1, 0, 0))
    world.add_cylinder(9, 0.037, 0.5, (0, 0, 0.25), IDENTITY, (1, 1, 1), _core.GROUP_ROBOT)
    world.set_background((0, 0, 1))
    rgb, depth = render(world, yaw_quaternion(math.pi / 2), ignore_handle=9)
    assert rgb[H // 2, W // 2, 0] > 0 and abs(depth[H // 2, W // 2] - 1.0) < 1e-3
    assert tuple(rgb[0, 0]) == (0, 0, 255)
    # Without the ignore, the camera sits inside the cylinder: everything is at near_m.
    _, depth = render(world, yaw_quaternion(math.pi / 2))
    assert np.all(depth == np.float32(0.01))
    # A mask without ROBOT does the same as the ignore.
    _, depth = render(world, yaw_quaternion(math.pi / 2), mask=_core.GROUP_STATIC)
    assert abs(depth[H // 2, W // 2] - 1.0) < 1e-3


def crowd(world, count=12):
    """A red wall, green spheres and ``count`` robot-like cylinders (handles 100...) in a ring
    around the camera, each carrying a camera looking outwards; returns their poses."""
    red_wall(world)
    for i in range(20):
        world.add_sphere(10 + i, 0.05, (1.5 + 0.1 * i, 0.1 * i - 1, 0.1), IDENTITY, (0, 1, 0))
    positions, quats = [], []
    for k in range(count):
        yaw = 2 * math.pi * k / count
        x, y = (0.3 + 0.05 * k) * math.cos(yaw), (0.3 + 0.05 * k) * math.sin(yaw)
        world.add_cylinder(100 + k, 0.037, 0.05, (x, y, 0.025), IDENTITY, (0.2, 0.4, 0.9),
                           _core.GROUP_ROBOT)
        positions.append((x + 0.03 * math.cos(yaw), y + 0.03 * math.sin(yaw), 0.03))
        quats.append(yaw_quaternion(yaw + 0.3 * (k % 3)))
    return np.array(positions), np.array(quats)


@pytest.mark.parametrize("threads", [1, 2, 5])
def test_a_batch_renders_each_image_as_render_does(world, threads):
    positions, quats = crowd(world)
    ignore = [100 + k for k in range(len(positions))]
    ignore[3] = -1          # this camera sits inside its own robot: everything at near_m
    images = world.render_rgb_batch(positions, quats, W, H, FOV, 0.01, 5.0, ignore,
                                    threads=threads)
    assert images.shape == (len(positions), H, W, 3) and images.dtype == np.uint8
    for k in range(len(positions)):
        rgb, _ = world.render(positions[k], quats[k], W, H, FOV, 0.01, 5.0, ignore[k])
        assert np.array_equal(images[k], rgb), f"image {k}"
    # the comparison can tell images apart: the scene gives many different ones (those that
    # see only the background are alike)
    assert len({images[k].tobytes() for k in range(len(positions))}) >= len(positions) // 2


def test_a_batch_is_checked_whole_before_anything_is_drawn(world):
    positions, quats = crowd(world, 4)
    ignore = [100, 101, 102, 103]
    assert world.render_rgb_batch(positions[:0], quats[:0], W, H, FOV, 0.01, 5.0,
                                  []).shape == (0, H, W, 3)
    bad_quats = quats.copy()
    bad_quats[2] = 0.0
    for args in ((positions, bad_quats, W, H, FOV, 0.01, 5.0, ignore),
                 (positions, quats, W, H, FOV, 0.01, 5.0, ignore[:3]),
                 (positions[:, :2], quats, W, H, FOV, 0.01, 5.0, ignore),
                 (positions, quats, W, H, FOV, 0.5, 0.1, ignore)):
        with pytest.raises(ValueError):
            world.render_rgb_batch(*args)
    with pytest.raises(ValueError):
        world.render_rgb_batch(positions, quats, W, H, FOV, 0.01, 5.0, ignore, threads=0)


@pytest.mark.parametrize(
    "width, height, fov, near, far",
    [(0, H, FOV, 0.01, 5.0), (W, H, 0.0, 0.01, 5.0), (W, H, math.pi, 0.01, 5.0),
     (W, H, FOV, 0.5, 0.1), (W, H, FOV, 0.0, 5.0), (W, H, FOV, 0.01, math.inf)],
)
def test_bad_camera_raises_value_error(world, width, height, fov, near, far):
    with pytest.raises(ValueError):
        world.render(CAMERA, IDENTITY, width, height, fov, near, far)
    with pytest.raises(ValueError):
        world.render(CAMERA, (0, 0, 0, 0), W, H, FOV, 0.01, 5.0)

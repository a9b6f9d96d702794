"""CollisionWorld.render against a brute-force reference, pixel for pixel (speed: bench/camera_render.py).

The reference casts one ray per pixel with CollisionWorld.ray_cast and shades it as ray_camera.hpp
states: pixel (row, col) looks along (1, -(col + 0.5 - W/2) / f, -(row + 0.5 - H/2) / f) in the
camera frame, depth = distance along the optical axis, colour = rgb (0.35 + 0.65 |n . L|). The
renderer culls objects per image and per pixel rectangle, so an object it wrongly dropped, or a
pixel it wrongly skipped, shows up here as a differing pixel. Scenes are random with fixed seeds.
"""
import math

import numpy as np
import pytest
from conftest import IDENTITY, add_arena

from epuck_vrep_compat import _core

LIGHT = np.array([0.4, 0.3, 0.866]) / np.linalg.norm([0.4, 0.3, 0.866])
BACKGROUND = (0.2, 0.4, 0.9)
GROUPS = (_core.GROUP_STATIC, _core.GROUP_ROBOT, _core.GROUP_DYNAMIC)


def rotation_matrix(quaternion):
    x, y, z, w = np.asarray(quaternion, float) / np.linalg.norm(quaternion)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def reference_render(world, colours, position, quaternion, width, height, fov, near, far,
                     ignore_handle=-1, mask=_core.GROUP_ALL):
    """One CollisionWorld.ray_cast per pixel: what render must equal."""
    focal = 0.5 * height / math.tan(0.5 * fov)
    rows, cols = np.mgrid[0:height, 0:width]
    rays = np.stack([np.ones((height, width)), -(cols + 0.5 - 0.5 * width) / focal,
                     -(rows + 0.5 - 0.5 * height) / focal], -1).reshape(-1, 3)
    length = np.linalg.norm(rays, axis=1)
    directions = rays @ rotation_matrix(quaternion).T  # ray_cast normalises them
    origins = np.tile(np.asarray(position, float), (len(rays), 1))
    distance, handle, normal = world.ray_cast(origins, directions, far * length.max(),
                                              ignore_handle, mask)
    hit = distance <= far * length
    depth = np.where(hit, np.clip(distance / length, near, far), far)
    table = {-1: BACKGROUND, **colours}
    base = np.array([table[h] if ok else BACKGROUND for h, ok in zip(handle, hit)])
    shade = np.where(hit, 0.35 + 0.65 * np.abs(normal @ LIGHT), 1.0)
    rgb = np.floor(255 * np.clip(base * shade[:, None], 0, 1) + 0.5)  # lround, half away from 0
    return rgb.reshape(height, width, 3), depth.reshape(height, width).astype(np.float32)


def assert_renders_like_reference(world, colours, position, quaternion, width=160, height=120,
                                  fov=math.radians(50), near=0.01, far=3.0, **kwargs):
    rgb, depth = world.render(position, quaternion, width, height, fov, near, far, **kwargs)
    expected_rgb, expected_depth = reference_render(world, colours, position, quaternion, width,
                                                    height, fov, near, far, **kwargs)
    colour_off = np.abs(rgb.astype(int) - expected_rgb).max(axis=-1) > 1  # ±1: rounding of n
    depth_off = np.abs(depth - expected_depth) > 1e-6 * np.maximum(expected_depth, 1.0)
    bad = colour_off | depth_off
    assert not bad.any(), (f"{bad.sum()} of {bad.size} pixels differ, first at "
                           f"{np.argwhere(bad)[0]}: {rgb[bad][0]} {depth[bad][0]} vs "
                           f"{expected_rgb[bad][0]} {expected_depth[bad][0]}")


def random_quaternion(rng):
    q = rng.normal(size=4)
    return tuple(q / np.linalg.norm(q))


def random_scene(world, seed, count=40):
    """A floor and `count` boxes, cylinders and spheres of every orientation; their colours."""
    rng = np.random.default_rng(seed)
    world.set_background(BACKGROUND)
    colours = {1: (0.8, 0.8, 0.7)}
    world.add_box(1, (2.0, 2.0, 0.01), (0, 0, -0.01), IDENTITY, colours[1], _core.GROUP_FLOOR)
    for handle in range(2, 2 + count):
        colour = tuple(rng.choice([0.0, 1.0, rng.uniform()]) for _ in range(3))
        position = (rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(0.0, 0.6))
        quaternion, group = random_quaternion(rng), int(rng.choice(GROUPS))
        kind = rng.integers(3)
        if kind == 0:
            world.add_box(handle, rng.uniform(0.005, 0.3, 3), position, quaternion, colour, group)
        elif kind == 1:
            world.add_cylinder(handle, rng.uniform(0.01, 0.2), rng.uniform(0.01, 0.5), position,
                               quaternion, colour, group)
        else:
            world.add_sphere(handle, rng.uniform(0.01, 0.2), position, quaternion, colour, group)
        colours[handle] = colour
    return colours


def free_cameras(world, seed, count):
    """Random camera poses, any orientation, none touching or inside an object."""
    rng = np.random.default_rng(seed)
    cameras = []
    while len(cameras) < count:
        position = (rng.uniform(-1.6, 1.6), rng.uniform(-1.6, 1.6), rng.uniform(0.02, 0.8))
        axes = np.vstack([np.eye(3), -np.eye(3)])
        distance, _, _ = world.ray_cast(np.tile(position, (6, 1)), axes, 10.0)
        if np.all(distance > 1e-3):
            cameras.append((position, random_quaternion(rng)))
    return cameras


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_scenes_match_one_ray_cast_per_pixel(world, seed):
    colours = random_scene(world, seed)
    for position, quaternion in free_cameras(world, seed, 4):
        assert_renders_like_reference(world, colours, position, quaternion)


@pytest.mark.parametrize("width, height, fov", [(40, 40, 0.6435), (7, 3, 2.5), (1, 1, 0.1),
                                                (33, 80, 1.2)])
def test_other_sizes_and_fields_of_view_match(world, width, height, fov):
    colours = random_scene(world, 4)
    for position, quaternion in free_cameras(world, 4, 3):
        assert_renders_like_reference(world, colours, position, quaternion, width, height, fov)


def test_mask_ignore_and_short_far_match(world):
    colours = random_scene(world, 5)
    (position, quaternion), = free_cameras(world, 5, 1)
    mask = _core.GROUP_STATIC | _core.GROUP_FLOOR
    assert_renders_like_reference(world, colours, position, quaternion, far=0.7, mask=mask)
    assert_renders_like_reference(world, colours, position, quaternion, ignore_handle=1)


def test_camera_inside_or_on_an_object_matches(world):
    # Inside, every ray hits at 0 m. On a face, looking in, likewise. (Looking out from a face
    # is not compared: whether ray_cast's broadphase visits the object then depends on Bullet's
    # box padding, while the closed form, and the renderer, count the touch as a hit at 0 m.)
    colours = random_scene(world, 6, count=10)
    colours[100] = (0.9, 0.1, 0.1)
    world.add_box(100, (0.5, 0.25, 0.25), (1.5, 0, 0.25), IDENTITY, colours[100])
    looking_back = (0.0, 0.0, 1.0, 0.0)
    for position, quaternion in [((1.5, 0.1, 0.2), IDENTITY), ((1.5, 0.1, 0.2), looking_back),
                                 ((1.0, 0.0, 0.25), IDENTITY), ((2.0, 0.0, 0.25), looking_back)]:
        assert_renders_like_reference(world, colours, position, quaternion)


def robot_arena(world, make_swarm, robots=100, seed=7):
    """`robots` e-pucks on a jittered grid with random headings; their camera poses."""
    rng = np.random.default_rng(seed)
    side = math.ceil(math.sqrt(robots))
    half_size = 0.075 * side + 0.05
    add_arena(world, half_size, first_handle=1)
    world.add_box(5, (half_size, half_size, 0.005), (0, 0, -0.005), IDENTITY, (1, 1, 1),
                  _core.GROUP_FLOOR)
    grid = [(100 + i, -half_size + 0.1 + 0.15 * (i % side) + rng.uniform(-0.02, 0.02),
             -half_size + 0.1 + 0.15 * (i // side) + rng.uniform(-0.02, 0.02),
             rng.uniform(-math.pi, math.pi)) for i in range(robots)]
    make_swarm(grid)
    colours = {h: (0.5, 0.5, 0.5) for h in range(1, 5)}
    colours[5] = (1.0, 1.0, 1.0)
    cameras = []
    for handle, x, y, yaw in grid:
        colours[handle] = (0.3, 0.6, 0.2)
        world.set_color(handle, colours[handle])
        position = (x + 0.037 * math.cos(yaw), y + 0.037 * math.sin(yaw), 0.028)
        cameras.append((handle, position, (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))))
    world.set_background(BACKGROUND)
    return colours, cameras


def test_robot_cameras_in_an_arena_match(world, make_swarm):
    colours, cameras = robot_arena(world, make_swarm)
    for handle, position, quaternion in cameras[::10]:
        assert_renders_like_reference(world, colours, position, quaternion, fov=0.6435,
                                      near=0.005, far=2.0, ignore_handle=handle)


def test_rendering_is_deterministic(world):
    random_scene(world, 8)
    (position, quaternion), = free_cameras(world, 8, 1)
    first = world.render(position, quaternion, 64, 48, 1.0, 0.01, 3.0)
    second = world.render(position, quaternion, 64, 48, 1.0, 0.01, 3.0)
    assert np.array_equal(first[0], second[0]) and np.array_equal(first[1], second[1])


@pytest.mark.parametrize("seed", [4, 5])
def test_depth_alone_and_colour_alone_are_renders_bit_for_bit(world, seed):
    """rgb=False skips the shading, depth=False the depth: the image asked for is render's."""
    random_scene(world, seed)
    cameras = free_cameras(world, seed, 6)
    cameras.append(((0.0, 0.0, -0.005), IDENTITY))     # inside the floor: every pixel at near_m
    for k, (position, quaternion) in enumerate(cameras):
        arguments = (position, quaternion, 96, 64, 1.0, 0.01, 2.5, -1,
                     (_core.GROUP_ALL, _core.GROUP_STATIC)[k % 2])
        rgb, depth = world.render(*arguments)
        no_rgb, depth_alone = world.render(*arguments, rgb=False)
        rgb_alone, no_depth = world.render(*arguments, depth=False)
        assert no_rgb is None and no_depth is None
        assert depth_alone.dtype == np.float32 and np.array_equal(depth_alone, depth)
        assert rgb_alone.shape == (64, 96, 3) and np.array_equal(rgb_alone, rgb)
        assert world.render(*arguments, rgb=False, depth=False) == (None, None)

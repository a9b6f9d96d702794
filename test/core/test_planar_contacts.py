"""Closed-form contacts (planar_contacts.hpp): robots against yawed boxes, robots, piles."""
import math

import numpy as np
from conftest import GREY, IDENTITY, still, yaw_quaternion

from epuck_vrep_compat import _core

RADIUS = 0.037
TOLERANCE = 1e-4  # ContactSettings::tolerance_m
FULL = 2 * math.pi
DT = 0.05


def rotate(yaw, x, y):
    return np.array([math.cos(yaw) * x - math.sin(yaw) * y, math.sin(yaw) * x + math.cos(yaw) * y])


def local(yaw, centre, point):
    """`point` in the frame of a rectangle centred at `centre`, turned by `yaw`."""
    return rotate(-yaw, *(np.asarray(point) - np.asarray(centre)))


def distance_to_rectangle(yaw, centre, half, point):
    outside = np.maximum(np.abs(local(yaw, centre, point)) - half, 0.0)
    return np.linalg.norm(outside)


def test_robot_stops_at_a_yawed_box_face(world, make_swarm):
    yaw = math.radians(30)
    along = rotate(yaw, 1.0, 0.0)
    world.add_box(1, (0.01, 0.2, 0.05), tuple(0.21 * along) + (0.05,), yaw_quaternion(yaw), GREY)
    swarm = make_swarm([(100, 0.0, 0.0, yaw)])  # face 0.2 m ahead, square to the heading
    for _ in range(60):
        swarm.step(DT, np.array([[FULL, FULL]]))
        assert swarm.poses[0, :2] @ along + RADIUS - 0.2 < 1e-9
    assert abs(swarm.poses[0, :2] @ along - (0.2 - RADIUS)) < 1e-5
    assert abs(swarm.poses[0, :2] @ rotate(yaw, 0.0, 1.0)) < 1e-12  # no sliding along it


def test_robot_driven_at_a_box_corner_stays_on_the_diagonal(world, make_swarm):
    yaw, half = 0.4, np.array([0.05, 0.05])
    centre = np.array([0.3, 0.1])
    world.add_box(1, (0.05, 0.05, 0.05), (centre[0], centre[1], 0.05), yaw_quaternion(yaw), GREY)
    corner = centre + rotate(yaw, -half[0], -half[1])
    outward = (corner - centre) / np.linalg.norm(corner - centre)
    start = corner + 0.15 * outward
    heading = math.atan2(-outward[1], -outward[0])
    swarm = make_swarm([(100, start[0], start[1], heading)])
    for _ in range(60):
        swarm.step(DT, np.array([[FULL, FULL]]))
        assert distance_to_rectangle(yaw, centre, half, swarm.poses[0, :2]) > RADIUS - 1e-9
    offset = swarm.poses[0, :2] - corner
    assert abs(np.linalg.norm(offset) - RADIUS) < 1e-5
    assert abs(offset @ np.array([-outward[1], outward[0]])) < 1e-9


def test_collinear_boxes_push_once_and_a_corner_along_both_walls(world, make_swarm):
    # In the frame of a yawed wall made of two boxes that meet where the first robot hits it,
    # with a second wall square to it, 0.49 m aside: the second robot drives into the corner.
    yaw = math.radians(-20)
    along, across = rotate(yaw, 1.0, 0.0), rotate(yaw, 0.0, 1.0)

    def add_wall(handle, half, centre):
        world.add_box(handle, half + (0.05,), tuple(centre) + (0.05,), yaw_quaternion(yaw), GREY)

    add_wall(1, (0.01, 0.1), 0.21 * along + 0.1 * across)
    add_wall(2, (0.01, 0.1), 0.21 * along - 0.1 * across)
    add_wall(3, (0.01, 0.2), 0.21 * along + 0.3 * across)
    add_wall(4, (0.3, 0.01), 0.5 * across)
    start = 0.3 * across
    swarm = make_swarm([(100, 0.0, 0.0, yaw), (101, start[0], start[1], yaw + 0.7)])
    for _ in range(120):
        swarm.step(DT, np.full((2, 2), FULL))
    first, second = swarm.poses[:, :2]
    assert abs(first @ along - (0.2 - RADIUS)) < 1e-5  # a 1 µm slop per step, not a double push
    assert abs(first @ across) < 1e-12
    assert abs(second @ along - (0.2 - RADIUS)) < 1e-5
    assert abs(second @ across - (0.49 - RADIUS)) < 1e-5


def test_robot_inside_a_box_leaves_through_the_nearest_face(world, make_swarm):
    # Deeper than the robot is tall: the push stays in the plane all the same.
    yaw, half = 0.5, np.array([0.03, 0.05])
    centres = [np.array([0.1, -0.05]), np.array([0.6, 0.3])]
    starts = [(0.01, 0.004), (0.004, -0.04)]  # nearest: the +x face, then the -y face
    for handle, centre in enumerate(centres, start=1):
        world.add_box(handle, (0.03, 0.05, 0.05), (centre[0], centre[1], 0.05),
                      yaw_quaternion(yaw), GREY)
    swarm = make_swarm([(100 + i, *(centre + rotate(yaw, *start)), 0.0)
                        for i, (centre, start) in enumerate(zip(centres, starts))])
    swarm.step(DT, still(swarm))
    first, second = (local(yaw, c, p) for c, p in zip(centres, swarm.poses[:, :2]))
    assert abs(first[0] - (half[0] + RADIUS)) < 1e-5 and abs(first[1] - 0.004) < 1e-12
    assert abs(second[1] + (half[1] + RADIUS)) < 1e-5 and abs(second[0] - 0.004) < 1e-12


def test_upright_cylinder_obstacle_and_a_box_above_the_robots(world, make_swarm):
    world.add_cylinder(1, 0.02, 0.1, (0.3, 0.0, 0.05), IDENTITY, GREY)
    world.add_box(2, (0.05, 0.5, 0.01), (0.2, 0.4, 0.06), IDENTITY, GREY)  # 5 mm above them
    swarm = make_swarm([(100, 0.0, 0.0, 0.0), (101, 0.0, 0.4, 0.0)])
    for _ in range(80):
        swarm.step(DT, np.full((2, 2), FULL))
    assert abs(swarm.poses[0, 0] - (0.3 - 0.02 - RADIUS)) < 1e-5
    assert swarm.poses[1, 0] > 0.4  # drove under the box


def test_head_on_robots_stop_without_sideways_creep(make_swarm):
    # Along a diagonal, so that every push has both components.
    start = 0.1 / math.sqrt(2)
    swarm = make_swarm([(100, -start, -start, math.pi / 4),
                        (101, start, start, -3 * math.pi / 4)])
    for _ in range(200):
        swarm.step(DT, np.full((2, 2), FULL))
        centres = swarm.poses[:, :2]
        assert np.linalg.norm(centres[0] - centres[1]) > 2 * RADIUS - TOLERANCE
    centres = swarm.poses[:, :2]
    assert np.abs(centres[:, 0] - centres[:, 1]).max() < 1e-9  # still on the diagonal
    assert abs(np.linalg.norm(centres[0] - centres[1]) - 2 * RADIUS) < 1e-5


def add_thick_arena(world, half_size_m):
    """Four 10 cm thick walls around a square of side 2 * half_size_m, overlapping at the
    corners (a pile can push a robot deep into a wall, and through a thin one)."""
    for handle, (x, y) in enumerate([(1, 0), (-1, 0), (0, 1), (0, -1)], start=1):
        half = (0.05, half_size_m + 0.1, 0.05) if x else (half_size_m + 0.1, 0.05, 0.05)
        world.add_box(handle, half, ((half_size_m + 0.05) * x, (half_size_m + 0.05) * y, 0.05),
                      IDENTITY, GREY)


def cluttered_jam(order):
    """24 robots in rows, driven into a wall where clutter waits that takes Bullet's path (a
    sphere, a tilted box) and the closed form's (a yawed box); the world is built in the given
    order, so Bullet's broadphase tree differs."""
    world = _core.CollisionWorld()
    builds = [lambda: world.add_sphere(10, 0.02, (0.22, -0.09, 0.02), IDENTITY, GREY,
                                       _core.GROUP_DYNAMIC),
              lambda: world.add_box(11, (0.02, 0.02, 0.02), (0.21, 0.0, 0.02),
                                    (0.3, 0.2, 0.1, 0.927), GREY),
              lambda: world.add_box(12, (0.015, 0.04, 0.03), (0.2, 0.12, 0.03),
                                    yaw_quaternion(0.6), GREY),
              lambda: add_thick_arena(world, 0.25)]
    for build in builds[::order]:
        build()
    swarm = _core.EpuckSwarm(world, _core.EpuckModel(), 3)
    for i in range(24):
        row, col = divmod(i, 6)
        swarm.add_robot(100 + i, -0.21 + 0.08 * col, -0.21 + 0.08 * row, 0.1 * (i % 3 - 1))
    swarm.set_slip_noise(np.full(24, 0.2))
    swarm.set_ir_noise(*(np.full((24, 8), v) for v in (0.3, 0.002, 0.001)))
    return swarm


def test_jammed_pile_ends_without_penetration(world):
    # 24 robots on two rings drive at a yawed box in the middle, with slip noise: the passes
    # run out while they push, and the pile settles once they stop.
    count = 24
    add_thick_arena(world, 0.3)
    world.add_box(20, (0.04, 0.02, 0.05), (0.0, 0.0, 0.05), yaw_quaternion(0.3), GREY)
    swarm = _core.EpuckSwarm(world, _core.EpuckModel(), 3)
    for i in range(count):
        angle, radius = 2 * math.pi * i / count, 0.22 if i % 2 else 0.14
        swarm.add_robot(100 + i, radius * math.cos(angle), radius * math.sin(angle),
                        angle + math.pi)
    swarm.set_slip_noise(np.full(count, 0.2))

    def deepest():
        centres = swarm.poses[:, :2]
        gaps = np.linalg.norm(centres[:, None] - centres[None], axis=-1) + np.eye(count)
        to_box = [distance_to_rectangle(0.3, (0, 0), (0.04, 0.02), c) for c in centres]
        return max(2 * RADIUS - gaps.min(), RADIUS - min(to_box))

    pushing = []
    for _ in range(100):
        swarm.step(DT, np.full((count, 2), 4.0))
        pushing.append(deepest())
    assert max(pushing) > 2 * TOLERANCE  # jammed: 16 passes were not enough
    for _ in range(30):
        swarm.step(DT, still(swarm))
    assert deepest() < TOLERANCE
    assert (np.linalg.norm(swarm.poses[:, :2], axis=1) < 0.15).sum() >= 12  # a pile it is


def test_jammed_run_is_bit_identical_whatever_the_build_order():
    runs = []
    for order in (1, -1):
        swarm = cluttered_jam(order)
        commands = np.random.default_rng(11).uniform(2.0, FULL, (200, swarm.size, 2))
        for command in commands:
            swarm.step(DT, command)
        runs.append([swarm.poses, swarm.ranges, swarm.velocities, swarm.detected_handles])
    for first, second in zip(*runs):
        assert np.array_equal(first, second)

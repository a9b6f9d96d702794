"""Contact resolution: robots stop at walls and at each other, never sink into them."""
import math

import numpy as np
from conftest import GREY, IDENTITY

from epuck_vrep_compat import _core

RADIUS = 0.037
FULL = 2 * math.pi
DT = 0.05


def test_robot_driven_into_a_wall_stops_at_it(world, make_swarm):
    world.add_box(1, (0.005, 0.5, 0.05), (0.205, 0, 0.05), IDENTITY, GREY)  # face at x = 0.2
    swarm = make_swarm()
    for _ in range(100):
        swarm.step(DT, np.array([[FULL, FULL]]))
        assert swarm.poses[0, 0] + RADIUS - 0.2 < 1e-3
    assert abs(swarm.poses[0, 0] - (0.2 - RADIUS)) < 1e-3
    assert abs(swarm.velocities[0, 0]) < 0.02 and abs(swarm.poses[0, 1]) < 1e-9


def test_oblique_approach_slides_along_the_wall(world, make_swarm):
    world.add_box(1, (0.005, 1.0, 0.05), (0.205, 0, 0.05), IDENTITY, GREY)
    swarm = make_swarm([(100, 0.0, 0.0, math.radians(45))])
    for _ in range(100):
        swarm.step(DT, np.array([[FULL, FULL]]))
        assert swarm.poses[0, 0] + RADIUS - 0.2 < 1e-3
    assert swarm.poses[0, 1] > 0.3  # the wall only stopped the x motion


def test_two_robots_head_on_stop_nose_to_nose(make_swarm):
    swarm = make_swarm([(100, -0.1, 0.0, 0.0), (101, 0.1, 0.0, math.pi)])
    for _ in range(100):
        swarm.step(DT, np.array([[FULL, FULL], [FULL, FULL]]))
        assert swarm.poses[1, 0] - swarm.poses[0, 0] > 2 * RADIUS - 1e-3
    assert np.allclose(swarm.poses[:, 0], [-RADIUS, RADIUS], atol=1e-3)


def test_offset_robots_slide_past_without_overlapping(make_swarm):
    swarm = make_swarm([(100, -0.1, 0.0, 0.0), (101, 0.1, 0.01, math.pi)])
    for _ in range(100):
        swarm.step(DT, np.array([[FULL, FULL], [FULL, FULL]]))
        gap = np.linalg.norm(swarm.poses[0, :2] - swarm.poses[1, :2])
        assert gap > 2 * RADIUS - 1e-3


def test_corner_holds_a_robot(world, make_swarm):
    world.add_box(1, (0.005, 0.5, 0.05), (0.205, 0, 0.05), IDENTITY, GREY)
    world.add_box(2, (0.5, 0.005, 0.05), (0, 0.205, 0.05), IDENTITY, GREY)
    swarm = make_swarm([(100, 0.0, 0.0, math.radians(40))])
    for _ in range(150):
        swarm.step(DT, np.array([[FULL, FULL]]))
    x, y, _ = swarm.poses[0]
    assert x + RADIUS - 0.2 < 1e-3 and y + RADIUS - 0.2 < 1e-3
    assert x > 0.2 - RADIUS - 1e-3 and y > 0.2 - RADIUS - 1e-3


def test_the_floor_never_blocks_but_dynamic_objects_do(world, make_swarm):
    # A floor whose top is 1 mm above the robot's bottom must not stop it.
    world.add_box(1, (1.0, 1.0, 0.005), (0, 0, -0.004), IDENTITY, GREY, _core.GROUP_FLOOR)
    world.add_sphere(2, 0.02, (0.3, 0.0, 0.02), IDENTITY, GREY, _core.GROUP_DYNAMIC)
    swarm = make_swarm()
    for _ in range(80):
        swarm.step(DT, np.array([[FULL, FULL]]))
    assert abs(swarm.poses[0, 0] - (0.3 - 0.02 - RADIUS)) < 1e-3

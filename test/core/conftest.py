"""Tiny fixtures for the core tests: worlds and swarms built in code, no ROS master."""
import math

import numpy as np
import pytest

from epuck_vrep_compat import _core

IDENTITY = (0.0, 0.0, 0.0, 1.0)
GREY = (0.5, 0.5, 0.5)


def yaw_quaternion(yaw):
    """Quaternion (x, y, z, w) of a rotation by yaw about z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


@pytest.fixture
def world():
    return _core.CollisionWorld()


@pytest.fixture
def make_swarm(world):
    """Returns a factory: make_swarm(robots=[(handle, x, y, yaw)], seed=1, model=None)."""

    def factory(robots=((100, 0.0, 0.0, 0.0),), seed=1, model=None):
        swarm = _core.EpuckSwarm(world, model or _core.EpuckModel(), seed)
        for handle, x, y, yaw in robots:
            swarm.add_robot(handle, x, y, yaw)
        return swarm

    return factory


def add_arena(world, half_size_m, first_handle=1):
    """Four 1 cm thick, 10 cm high walls around a square of side 2 * half_size_m."""
    thickness = 0.005
    walls = [
        ((thickness, half_size_m, 0.05), (half_size_m + thickness, 0.0, 0.05)),
        ((thickness, half_size_m, 0.05), (-half_size_m - thickness, 0.0, 0.05)),
        ((half_size_m, thickness, 0.05), (0.0, half_size_m + thickness, 0.05)),
        ((half_size_m, thickness, 0.05), (0.0, -half_size_m - thickness, 0.05)),
    ]
    for i, (half, position) in enumerate(walls):
        world.add_box(first_handle + i, half, position, IDENTITY, GREY)


def still(swarm):
    """Zero wheel commands for every robot."""
    return np.zeros((swarm.size, 2))

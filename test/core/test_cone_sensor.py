"""ConeSensor: sampled cones against analytic distances (sensor 0 of a robot at the origin)."""
import math

import numpy as np
import pytest
from conftest import GREY, IDENTITY, still, yaw_quaternion

from epuck_vrep_compat import _core

ROBOT = 100
WALL = 1
TOLERANCE_M = 1e-3


def sensor_frame(swarm, index=0):
    """Origin and heading of a level sensor of the robot standing at the origin, yaw 0."""
    sensor = swarm.sensor_model(index)
    return np.array(sensor.position), sensor.yaw_rad, sensor.half_angle_rad


def place_wall(world, origin, heading, distance_m):
    """A wall whose normal points back along `heading`, `distance_m` from `origin`."""
    direction = np.array([math.cos(heading), math.sin(heading), 0.0])
    centre = origin + (distance_m + 0.005) * direction
    if world.has(WALL):
        world.set_pose(WALL, centre, yaw_quaternion(heading))
    else:
        world.add_box(WALL, (0.005, 0.1, 0.1), centre, yaw_quaternion(heading), GREY)


def read(swarm, index=0):
    swarm.step(0.05, still(swarm))
    return swarm.ranges_clean[0, index], swarm.detected_handles[0, index]


def test_default_cone(make_swarm):
    sensor = make_swarm().sensor_model(0)
    assert sensor.half_angle_rad == pytest.approx(math.radians(15))
    assert (sensor.min_range_m, sensor.max_range_m, sensor.rings, sensor.azimuths) == (
        0.0015, 0.05, 2, 16)


@pytest.mark.parametrize("distance_m", [0.005, 0.01, 0.02, 0.03, 0.04, 0.049])
def test_perpendicular_wall(world, make_swarm, distance_m):
    swarm = make_swarm()
    origin, yaw, _ = sensor_frame(swarm)
    place_wall(world, origin, yaw, distance_m)
    reading, handle = read(swarm)
    assert abs(reading - distance_m) < TOLERANCE_M and handle == WALL
    assert np.allclose(swarm.detected_points[0, 0], (distance_m, 0, 0), atol=TOLERANCE_M)
    assert np.allclose(swarm.detected_normals[0, 0], (-1, 0, 0), atol=1e-9)


@pytest.mark.parametrize("angle_deg", [-60, -40, 25, 40, 60])
def test_wall_normal_outside_the_cone(world, make_swarm, angle_deg):
    swarm = make_swarm()
    origin, yaw, half_angle = sensor_frame(swarm)
    angle = math.radians(angle_deg)
    place_wall(world, origin, yaw + angle, 0.025)
    reading, _ = read(swarm)
    assert abs(reading - 0.025 / math.cos(abs(angle) - half_angle)) < TOLERANCE_M


@pytest.mark.parametrize("angle_deg", [-10, 4, 12])
def test_wall_normal_inside_the_cone(world, make_swarm, angle_deg):
    swarm = make_swarm()
    origin, yaw, _ = sensor_frame(swarm)
    place_wall(world, origin, yaw + math.radians(angle_deg), 0.045)
    reading, _ = read(swarm)
    assert abs(reading - 0.045) < TOLERANCE_M


def test_nothing_in_range_reads_max(world, make_swarm):
    swarm = make_swarm()
    origin, yaw, _ = sensor_frame(swarm)
    place_wall(world, origin, yaw, 0.051)
    reading, handle = read(swarm)
    assert reading == 0.05 and handle == -1
    assert not swarm.detected_points[0, 0].any()


@pytest.mark.parametrize(
    "offset_deg, radius_m, reading_m",
    [(0, 0.02, 0.035), (8, 0.02, 0.035), (-25, 0.02, 0.035),
     (11.25, 0.01, 0.049)],  # the worst case: the closest point midway between rings, at 5 cm
)
def test_vertical_cylinder(world, make_swarm, offset_deg, radius_m, reading_m):
    swarm = make_swarm()
    origin, yaw, half_angle = sensor_frame(swarm)
    centre_distance = reading_m + radius_m
    bearing = yaw + math.radians(offset_deg)
    centre = origin + centre_distance * np.array([math.cos(bearing), math.sin(bearing), 0])
    world.add_cylinder(WALL, radius_m, 0.1, centre, IDENTITY, GREY)
    # Closest point inside the cone, or else along the cone's horizontal edge.
    beta = max(0.0, abs(math.radians(offset_deg)) - half_angle)
    expected = (centre_distance * math.cos(beta)
                - math.sqrt(radius_m**2 - (centre_distance * math.sin(beta))**2))
    reading, handle = read(swarm)
    assert abs(reading - expected) < TOLERANCE_M and handle == WALL


def test_pitched_sensor_sees_a_low_step(world, make_swarm):
    pitch = math.radians(45)
    sensor = _core.ConeSensor(position=(0.035, 0.0, 0.034), pitch_rad=pitch)
    swarm = make_swarm(model=_core.EpuckModel(sensors=[sensor]))
    world.add_box(WALL, (0.08, 0.1, 0.005), (0.12, 0, 0.005), IDENTITY, GREY)  # top at 1 cm
    reading, handle = read(swarm)
    drop = 0.034 - 0.01
    # The floor-ward normal is 90° - pitch from the axis, outside the cone: the edge ray reads.
    angle_to_normal = math.pi / 2 - pitch
    assert handle == WALL
    assert abs(reading - drop / math.cos(angle_to_normal - sensor.half_angle_rad)) < TOLERANCE_M


def test_own_body_never_detected(world, make_swarm):
    swarm = make_swarm([(100, 0.0, 0.0, 0.0), (101, 0.1, 0.0, math.pi)])
    swarm.step(0.05, still(swarm))
    handles = swarm.detected_handles
    assert 100 not in handles[0] and 101 not in handles[1]
    assert handles[0, 0] == 101 and handles[0, 7] == 101
    assert handles[0, 3] == -1 and swarm.ranges_clean[0, 3] == 0.05

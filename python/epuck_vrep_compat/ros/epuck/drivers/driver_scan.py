"""The real driver's 19-beam ``LaserScan`` emulation, computed from the 8 IR readings.

epuck_driver_cpp turns IR values into a scan over -90..+90 degrees in 10 degree steps: each beam
interpolates the raw intensities of the two neighbouring front/side sensors (P2, P1, P0, P7, P6,
P5) by angle, converts with the driver's field formula distance = 0.5 / sqrt(raw) and adds the
robot radius. Our readings are distances, so raw = (0.5 / d)^2, and "nothing detected" is raw 0.
"""
import math

import numpy as np

from epuck_vrep_compat.ros.epuck.profiles import ROBOT_RADIUS_M, SCAN_BEAMS

ANGLE_MIN = -math.pi / 2
ANGLE_MAX = math.pi / 2
ANGLE_INCREMENT = math.pi / 18
RANGE_MIN = 0.005 + ROBOT_RADIUS_M
RANGE_MAX = 0.05 + ROBOT_RADIUS_M
SENSORS_RIGHT_TO_LEFT = (2, 1, 0, 7, 6, 5)


def scan_from_ranges(ranges_m, max_range_m, sensor_yaws_rad):
    """(ranges (19,), intensities (19,)) from one robot's 8 IR distances."""
    order = list(SENSORS_RIGHT_TO_LEFT)
    yaws = np.array([sensor_yaws_rad[i] for i in order])
    d = np.array([ranges_m[i] for i in order], dtype=float)
    raw = np.where(d < max_range_m, (0.5 / np.maximum(d, 1e-6)) ** 2, 0.0)
    beams = ANGLE_MIN + ANGLE_INCREMENT * np.arange(SCAN_BEAMS)
    raw_beams = np.interp(beams, yaws, raw)
    with np.errstate(divide="ignore"):
        ranges = np.where(raw_beams > 0.0, 0.5 / np.sqrt(np.maximum(raw_beams, 1e-12))
                          + ROBOT_RADIUS_M, RANGE_MAX)
    return np.clip(ranges, RANGE_MIN, RANGE_MAX), raw_beams

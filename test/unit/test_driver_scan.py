"""The driver's laser-scan emulation from IR distances."""
import numpy as np
import pytest

from epuck_vrep_compat.ros.epuck.drivers import driver_scan

YAWS = np.deg2rad([-17.2, -45.9, -90.0, -151.5, 151.2, 90.0, 45.8, 17.1])


def test_nothing_detected_gives_range_max():
    ranges, intensities = driver_scan.scan_from_ranges([0.05] * 8, 0.05, YAWS)
    assert len(ranges) == 19
    assert np.all(ranges == pytest.approx(driver_scan.RANGE_MAX))
    assert np.all(intensities == 0.0)


def test_beam_on_a_sensor_axis_reproduces_its_distance_plus_radius():
    d = [0.05] * 8
    d[2] = 0.02            # right sensor, -90 degrees = beam 0
    ranges, _ = driver_scan.scan_from_ranges(d, 0.05, YAWS)
    assert ranges[0] == pytest.approx(0.02 + 0.035)
    assert np.all(ranges >= driver_scan.RANGE_MIN) and np.all(ranges <= driver_scan.RANGE_MAX)

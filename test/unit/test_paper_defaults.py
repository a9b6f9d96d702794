"""With no parameters given the simulated e-puck is the paper's real one (section 4.1), and the
other presets are what they claim: statistics over simulated time, sample sizes chosen so the
tolerances mean something (SE of a fraction near 0.16 over 12 000 readings: 0.0034; of a SD
over 4 000 samples: 1.1 %)."""
import math

import numpy as np
import pytest

from epuck_vrep_compat import CollisionWorld, EpuckModel, EpuckSwarm
from epuck_vrep_compat.epuck import paper_robot as paper
from epuck_vrep_compat.epuck.noise import NoiseSettings
from epuck_vrep_compat.epuck.noise_presets import preset

STEP_S = 0.05
WHEEL_RADIUS_M = 0.02


def run(settings, speed_m_s, steps, seed=3):
    """One robot in open space (nothing within sensing range), driving straight at speed_m_s:
    (accelerometer, gyroscope, proximity) per step, the first two steps left out (no
    acceleration history yet, then the start's jump)."""
    swarm = EpuckSwarm(CollisionWorld(), EpuckModel(), seed)
    swarm.add_robot(10, 0.0, 0.0, 0.0)
    settings.apply(swarm, ["ePuck0"])
    wheel = np.full((1, 2), speed_m_s / WHEEL_RADIUS_M)
    accel, gyro, ranges = [], [], []
    for _ in range(steps + 2):
        swarm.step(STEP_S, wheel)
        accel.append(swarm.accel[0].copy())
        gyro.append(swarm.gyro[0].copy())
        ranges.append(swarm.ranges[0].copy())
    return np.array(accel[2:]), np.array(gyro[2:]), np.array(ranges[2:])


def test_sensor_0_is_wrong_in_16_percent_of_readings_in_open_space():
    _, _, ranges = run(NoiseSettings(), 0.0, 12000)
    wrong = ranges[:, 0] < 0.05
    assert abs(wrong.mean() - 61 / 380) < 0.011, wrong.mean()
    assert abs(wrong.mean() - 0.16) < 3 * math.sqrt(0.16 * 0.84 / wrong.size)
    # The errors are one-sided and their size has the configured mean and SD.
    errors = 0.05 - ranges[wrong, 0]
    se = paper.IR_STDDEV_M / math.sqrt(errors.size)
    assert abs(errors.mean() - paper.IR_MEAN_M) < 3 * se
    assert abs(errors.std(ddof=1) - paper.IR_STDDEV_M) < 3 * paper.IR_STDDEV_M / math.sqrt(
        2 * errors.size)


def test_accelerometer_driving_straight_matches_table_1_real_row():
    accel, _, _ = run(NoiseSettings(), paper.PAPER_SPEED_M_S, 4000)
    mean, sd = accel.mean(axis=0), accel.std(axis=0, ddof=1)
    target_mean = np.array(paper.TABLE1_REAL_MEAN_M_S2)
    target_sd = np.array(paper.TABLE1_REAL_STDDEV_M_S2)
    np.testing.assert_array_less(np.abs(mean - target_mean), 0.05)         # the bound
    np.testing.assert_array_less(np.abs(sd / target_sd - 1.0), 0.10)
    # And closer: within 3 SE of Table 1, so slip noise is not counted twice on x.
    np.testing.assert_array_less(np.abs(mean - target_mean), 3 * target_sd / math.sqrt(4000))
    np.testing.assert_array_less(np.abs(sd / target_sd - 1.0), 3 / math.sqrt(2 * 3999))


def test_at_rest_the_accelerometer_keeps_the_bias_and_only_the_sensors_own_noise():
    accel, gyro, _ = run(NoiseSettings(), 0.0, 4000)
    np.testing.assert_allclose(accel.mean(axis=0), paper.TABLE1_REAL_MEAN_M_S2,
                               atol=3 * 0.05 / math.sqrt(4000))
    np.testing.assert_allclose(accel.std(axis=0, ddof=1), paper.ACCEL_STDDEV_M_S2,
                               rtol=3 / math.sqrt(2 * 3999))
    assert paper.ACCEL_STDDEV_M_S2[0] < paper.TABLE1_REAL_STDDEV_M_S2[0]     # slip's part off
    np.testing.assert_allclose(gyro.std(axis=0, ddof=1), paper.GYRO_STDDEV,
                               rtol=3 / math.sqrt(2 * 3999))


def test_vrep_preset_is_table_1_simulated_row_with_exact_proximity():
    accel, gyro, ranges = run(preset("vrep"), paper.PAPER_SPEED_M_S, 4000)
    # V-REP reads -g on z; ours +g (~accel_sign: vrep flips it on the wire).
    vrep_mean = np.array(paper.TABLE1_VREP_MEAN_M_S2) * (1, 1, -1)
    np.testing.assert_array_less(np.abs(accel.mean(axis=0) - vrep_mean), 0.05)
    np.testing.assert_allclose(accel.std(axis=0, ddof=1), paper.TABLE1_VREP_STDDEV_M_S2,
                               rtol=0.10)
    assert np.all(ranges == 0.05) and np.all(gyro == 0.0)


@pytest.mark.parametrize("speed", [0.0, paper.PAPER_SPEED_M_S])
def test_ideal_preset_is_exact(speed):
    accel, gyro, ranges = run(preset("ideal"), speed, 200)
    np.testing.assert_allclose(accel, np.tile([0.0, 0.0, 9.81], (200, 1)), atol=1e-9)
    assert np.all(ranges == 0.05) and np.all(gyro == 0.0)

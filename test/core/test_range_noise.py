"""apply_range_noise: the V-REP e-puck script's proximity noise model."""
import math

import numpy as np
import pytest

from epuck_vrep_compat import _core

MIN, MAX = 0.0015, 0.05


def test_noisy_fraction_and_magnitude_statistics():
    clean = np.full(10000, 0.025)  # mid-range: far from both clamps
    mean, sd = 0.002, 0.0005
    noisy, applied = _core.apply_range_noise(clean, MIN, MAX, 0.16, mean, sd, 11)
    assert applied.dtype == bool and noisy.shape == clean.shape
    assert abs(applied.mean() - 0.16) < 0.011
    assert np.array_equal(noisy[~applied], clean[~applied])
    offsets = noisy[applied] - clean[applied]
    magnitude = np.abs(offsets)
    n = magnitude.size
    assert abs(magnitude.mean() - mean) < 3 * sd / math.sqrt(n)
    assert abs(magnitude.std(ddof=1) - sd) < 3 * sd / math.sqrt(2 * (n - 1))
    # Away from the clamps the sign is a fair coin.
    assert abs((offsets > 0).mean() - 0.5) < 3 * 0.5 / math.sqrt(n)


def test_readings_stay_inside_the_range():
    clean = np.linspace(MIN, MAX, 5000)
    noisy, _ = _core.apply_range_noise(clean, MIN, MAX, 1.0, 0.0, 0.05, 3)
    assert noisy.min() >= MIN and noisy.max() <= MAX


def test_sign_rule_at_the_limits():
    mean, sd = 0.004, 0.0005
    at_min, applied = _core.apply_range_noise(np.full(200, MIN), MIN, MAX, 1.0, mean, sd, 4)
    assert applied.all() and (at_min > MIN).all()
    at_max, applied = _core.apply_range_noise(np.full(200, MAX), MIN, MAX, 1.0, mean, sd, 4)
    assert applied.all() and (at_max < MAX).all()


def test_same_seed_same_noise_and_probability_zero_changes_nothing():
    clean = np.linspace(0.01, 0.04, 50)
    a = _core.apply_range_noise(clean, MIN, MAX, 0.5, 0.001, 0.001, 9)
    b = _core.apply_range_noise(clean, MIN, MAX, 0.5, 0.001, 0.001, 9)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    noisy, applied = _core.apply_range_noise(clean, MIN, MAX, 0.0, 0.001, 0.001, 9)
    assert np.array_equal(noisy, clean) and not applied.any()


@pytest.mark.parametrize(
    "probability, stddev, clean",
    [(1.5, 0.001, 0.02), (-0.1, 0.001, 0.02), (0.5, -0.001, 0.02), (math.nan, 0.001, 0.02),
     (0.5, 0.001, math.nan)],
)
def test_bad_parameters_raise_value_error(probability, stddev, clean):
    with pytest.raises(ValueError):
        _core.apply_range_noise(np.array([clean]), MIN, MAX, probability, 0.0, stddev, 1)


def test_no_error_vanishes_in_the_clamp_at_max_range():
    # Mean 0: a signed draw would lengthen half of the readings at max range, and the clamp
    # would hide them (p = 0.16 showing as 0.08). The error's size is folded, so all show.
    clean = np.full(20000, MAX)
    noisy, applied = _core.apply_range_noise(clean, MIN, MAX, 0.16, 0.0, 0.003, 5)
    wrong = noisy < MAX
    assert np.array_equal(wrong, applied)
    assert abs(wrong.mean() - 0.16) < 3 * math.sqrt(0.16 * 0.84 / clean.size)
    # |N(0, sd)| has mean sd·√(2/π).
    errors = MAX - noisy[wrong]
    assert abs(errors.mean() - 0.003 * math.sqrt(2 / math.pi)) < 3 * 0.003 / math.sqrt(errors.size)

"""Rng: the seeded generator every noise source uses."""
import math

import numpy as np

from epuck_vrep_compat import _core


def test_same_seed_same_stream():
    a, b = _core.Rng(123), _core.Rng(123)
    assert [a.uniform() for _ in range(100)] == [b.uniform() for _ in range(100)]
    assert a.state_digest() == b.state_digest()


def test_different_seeds_differ():
    assert _core.Rng(1).uniform() != _core.Rng(2).uniform()
    assert _core.Rng(1).state_digest() != _core.Rng(2).state_digest()


def test_uniform_is_in_half_open_unit_interval_with_the_right_moments():
    rng = _core.Rng(7)
    u = np.array([rng.uniform() for _ in range(20000)])
    assert u.min() > 0.0 and u.max() <= 1.0
    assert abs(u.mean() - 0.5) < 3 * math.sqrt(1 / 12 / u.size)


def test_normal_is_box_muller_cos_branch_of_two_uniforms():
    a, b = _core.Rng(99), _core.Rng(99)
    for _ in range(10):
        u1, u2 = a.uniform(), a.uniform()
        assert b.normal() == math.sqrt(-2 * math.log(u1)) * math.cos(2 * math.pi * u2)


def test_normal_moments():
    rng = _core.Rng(5)
    x = np.array([rng.normal() for _ in range(20000)])
    assert abs(x.mean()) < 3 / math.sqrt(x.size)
    assert abs(x.std(ddof=1) - 1) < 3 / math.sqrt(2 * (x.size - 1))

"""cmd_vel scalings and cmd_led semantics (pure logic)."""
import math

import pytest

from epuck_vrep_compat.ros.epuck.commands import apply_led_command, wheel_speeds

R, L = 0.02, 0.053


def test_si_is_rep103_kinematics():
    left, right = wheel_speeds("si", 0.1, 0.0, R, L)
    assert left == pytest.approx(5.0) and right == pytest.approx(5.0)
    left, right = wheel_speeds("si", 0.0, 1.0, R, L)
    assert right == pytest.approx(L / 2 / R) and left == pytest.approx(-L / 2 / R)


def test_vrep_scaling_is_the_scripts_formula():
    left, right = wheel_speeds("vrep", 0.1, 0.5, R, L)
    assert left == pytest.approx((0.1 * 8.9 - 26.5 * 0.5) / 40.0)
    assert right == pytest.approx((0.1 * 8.9 + 26.5 * 0.5) / 40.0)
    # the script's closed form for model scale 1: wL = 0.2225 v - 0.6625 w
    assert left == pytest.approx(0.2225 * 0.1 - 0.6625 * 0.5)


def test_driver_scaling_truncates_to_motor_steps():
    left, right = wheel_speeds("epuck_driver", 1.0, 0.0, R, L)
    steps = int((1.0 / 3.0) / 4.0 * 1000.0)          # 83 steps/s
    assert left == pytest.approx(steps * 2 * math.pi / 1000.0)
    assert right == left


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_input_is_refused(bad):
    for scaling in ("si", "vrep", "epuck_driver"):
        assert wheel_speeds(scaling, bad, 0.0, R, L) is None
        assert wheel_speeds(scaling, 0.0, bad, R, L) is None


def test_huge_finite_input_gives_finite_speeds():
    for scaling in ("si", "vrep", "epuck_driver"):
        speeds = wheel_speeds(scaling, 1e308, -1e308, R, L)
        assert all(math.isfinite(s) for s in speeds)


def test_vrep_leds_missing_entries_are_off_and_value_2_is_off():
    state = apply_led_command("vrep", [0] * 10, bytearray([1, 0, 2]))
    assert state == [1, 0, 0, 0, 0, 0, 0, 0, 0, 0]


def test_driver_leds_toggle_and_length():
    current = [0, 1] + [0] * 8
    state = apply_led_command("epuck_driver", current, bytearray([2, 2, 1] + [0] * 7))
    assert state[:3] == [1, 0, 1]
    assert isinstance(apply_led_command("epuck_driver", current, bytearray([1] * 9)), str)
    assert isinstance(apply_led_command("epuck_driver", current, bytearray([3] * 10)), str)
    assert isinstance(apply_led_command("vrep", current, bytearray()), str)
    assert isinstance(apply_led_command("vrep", current, bytearray([1] * 11)), str)

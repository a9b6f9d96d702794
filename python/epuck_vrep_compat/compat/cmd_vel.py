"""The ``cmd_vel`` scalings, both ways: a Twist to wheel speeds as the simulator (and the original
it reproduces) reads it, and wheel speeds to the Twist that gives them, for clients that think
in wheels (``policy_node``). Written once, here.

* ``si``: REP 103, linear.x in m/s and angular.z in rad/s, turned into wheel speeds with the
  e-puck's geometry.
* ``vrep``: exactly the V-REP model's script: linear = 8.9 * linear.x, wheel = (linear -+ 26.5 *
  angular.z) / 40 applied directly as joint speed in rad/s (its "mm" constants).
* ``epuck_driver``: exactly the real driver: linear and angular divided by 3, wheel =
  (linear -+ 2.65 * angular) / 4 in revolutions/s, truncated to integer motor steps (1000 per
  revolution) as the firmware receives them.

In every convention the simulator then clamps to the motors' 1000 steps/s, keeping the curvature.
"""
import math

SCALINGS = ("si", "vrep", "epuck_driver")
# Each topic profile's default scaling: its original's (the simulator's ~cmd_vel_scaling default)
PROFILE_SCALINGS = {"vrep": "vrep", "epuck_driver": "epuck_driver",
                    "epuck2_driver": "epuck_driver"}
# The e-puck's geometry and motor limit (the C++ core's EpuckModel defaults, which
# test/core/test_epuck_model.py holds these to): for clients, which load no core.
WHEEL_RADIUS_M = 0.02
WHEEL_SEPARATION_M = 0.053
STEPS_PER_REVOLUTION = 1000
MAX_WHEEL_SPEED_RAD_S = 2.0 * math.pi * 1000 / STEPS_PER_REVOLUTION    # 1000 steps/s
_INPUT_LIMIT = 1.0e3     # |v|, |w| beyond this are clamped before any arithmetic (no overflow)
_VREP_LINEAR, _VREP_TURN, _VREP_WHEEL = 8.9, 26.5, 40.0
_DRIVER_DIVISOR, _DRIVER_TURN, _DRIVER_WHEEL = 3.0, 2.65, 4.0
_STEP_RAD = 2.0 * math.pi / STEPS_PER_REVOLUTION


def wheel_speeds(scaling: str, linear_x: float, angular_z: float,
                 wheel_radius_m: float = WHEEL_RADIUS_M,
                 wheel_separation_m: float = WHEEL_SEPARATION_M):
    """(left, right) wheel speeds [rad/s], or None when an input is not finite."""
    if not (math.isfinite(linear_x) and math.isfinite(angular_z)):
        return None
    v = min(max(linear_x, -_INPUT_LIMIT), _INPUT_LIMIT)
    w = min(max(angular_z, -_INPUT_LIMIT), _INPUT_LIMIT)
    if scaling == "si":
        half = 0.5 * wheel_separation_m
        return (v - half * w) / wheel_radius_m, (v + half * w) / wheel_radius_m
    if scaling == "vrep":
        linear = v * _VREP_LINEAR
        return ((linear - _VREP_TURN * w) / _VREP_WHEEL, (linear + _VREP_TURN * w) / _VREP_WHEEL)
    if scaling == "epuck_driver":
        linear, angular = v / _DRIVER_DIVISOR, w / _DRIVER_DIVISOR
        steps = [int(((linear + sign * _DRIVER_TURN * angular) / _DRIVER_WHEEL)
                     * STEPS_PER_REVOLUTION) for sign in (-1.0, 1.0)]
        return tuple(s * _STEP_RAD for s in steps)
    raise ValueError(f"unknown cmd_vel scaling '{scaling}'")


def twist_for_wheels(scaling: str, left_rad_s: float, right_rad_s: float,
                     wheel_radius_m: float = WHEEL_RADIUS_M,
                     wheel_separation_m: float = WHEEL_SEPARATION_M):
    """(linear.x, angular.z) that :func:`wheel_speeds` turns into these wheel speeds [rad/s]
    in ``scaling``; in ``epuck_driver`` the nearest whole motor steps (the Twist aims at the
    middle of the step, so the driver's truncation lands on it)."""
    if scaling == "si":
        r = wheel_radius_m
        return (0.5 * r * (left_rad_s + right_rad_s),
                r * (right_rad_s - left_rad_s) / wheel_separation_m)
    if scaling == "vrep":
        left, right = left_rad_s * _VREP_WHEEL, right_rad_s * _VREP_WHEEL
        return 0.5 * (left + right) / _VREP_LINEAR, 0.5 * (right - left) / _VREP_TURN
    if scaling == "epuck_driver":
        revs = []
        for speed in (left_rad_s, right_rad_s):
            steps = round(speed / _STEP_RAD)
            revs.append((steps + math.copysign(0.5, steps) if steps else 0.0)
                        / STEPS_PER_REVOLUTION * _DRIVER_WHEEL)
        left, right = revs
        return (_DRIVER_DIVISOR * 0.5 * (left + right),
                _DRIVER_DIVISOR * 0.5 * (right - left) / _DRIVER_TURN)
    raise ValueError(f"unknown cmd_vel scaling '{scaling}'")

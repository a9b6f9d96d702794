"""Pure logic of the command topics: cmd_vel scalings and cmd_led semantics.

``cmd_vel`` conventions (parameter ``~cmd_vel_scaling``):

* ``si`` (default): REP 103, linear.x in m/s and angular.z in rad/s, turned into wheel speeds with
  the e-puck's geometry.
* ``vrep``: exactly the V-REP model's script: linear = 8.9 * linear.x, wheel = (linear -+ 26.5 *
  angular.z) / 40 applied directly as joint speed in rad/s (its "mm" constants).
* ``epuck_driver``: exactly the real driver: linear and angular divided by 3, wheel =
  (linear -+ 2.65 * angular) / 4 in revolutions/s, truncated to integer motor steps (1000 per
  revolution) as the firmware receives them.

In every convention the core then clamps to the motors' 1000 steps/s, keeping the curvature.
"""
import math

from epuck_vrep_compat.ros.epuck.drivers import epuck2_leds
from epuck_vrep_compat.epuck.leds import LED_COUNT

SCALINGS = ("si", "vrep", "epuck_driver")
_INPUT_LIMIT = 1.0e3     # |v|, |w| beyond this are clamped before any arithmetic (no overflow)


def wheel_speeds(scaling: str, linear_x: float, angular_z: float, wheel_radius_m: float,
                 wheel_separation_m: float):
    """(left, right) wheel speeds [rad/s], or None when an input is not finite."""
    if not (math.isfinite(linear_x) and math.isfinite(angular_z)):
        return None
    v = min(max(linear_x, -_INPUT_LIMIT), _INPUT_LIMIT)
    w = min(max(angular_z, -_INPUT_LIMIT), _INPUT_LIMIT)
    if scaling == "si":
        half = 0.5 * wheel_separation_m
        return (v - half * w) / wheel_radius_m, (v + half * w) / wheel_radius_m
    if scaling == "vrep":
        linear = v * 8.9
        return (linear - 26.5 * w) / 40.0, (linear + 26.5 * w) / 40.0
    if scaling == "epuck_driver":
        linear, angular = v / 3.0, w / 3.0
        steps = [int(((linear + sign * 2.65 * angular) / 4.0) * 1000.0) for sign in (-1.0, 1.0)]
        return tuple(s * 2.0 * math.pi / 1000.0 for s in steps)
    raise ValueError(f"unknown cmd_vel scaling '{scaling}'")




def apply_led_command(profile: str, current, data):
    """New LED states (10 values, 1 = on) from a cmd_led array, or an error string.

    ``vrep``: the model reads data[0..8]; 1 turns a LED on, anything else (or a missing entry)
    turns it off, data[9] is ignored. ``epuck_driver``: exactly 10 entries, 0 = off, 1 = on,
    2 = toggle, as the driver's firmware protocol.
    """
    values = list(data)
    if profile == "epuck2_driver":
        return epuck2_leds.apply_led_command(current, values)
    if profile == "vrep":
        if not 1 <= len(values) <= LED_COUNT:
            return f"cmd_led needs 1 to {LED_COUNT} entries, got {len(values)}"
        state = [1 if (k < len(values) and values[k] == 1) else 0 for k in range(9)]
        return state + [current[9]]
    if len(values) != LED_COUNT:
        return f"cmd_led needs exactly {LED_COUNT} entries, got {len(values)}"
    if any(v > 2 for v in values):
        return f"cmd_led values must be 0 (off), 1 (on) or 2 (toggle), got {values}"
    return [(1 - c) if v == 2 else v for v, c in zip(values, current)]

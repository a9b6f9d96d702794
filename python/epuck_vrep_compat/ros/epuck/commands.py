"""Pure logic of the command topics: cmd_vel scalings (written once in
:mod:`epuck_vrep_compat.compat.cmd_vel`, both ways, and re-exported here) and cmd_led semantics.
"""
from epuck_vrep_compat.compat.cmd_vel import SCALINGS, wheel_speeds  # noqa: F401 (re-exported)
from epuck_vrep_compat.ros.epuck.drivers import epuck2_leds
from epuck_vrep_compat.epuck.leds import LED_COUNT


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

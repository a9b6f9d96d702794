"""The e-puck2 driver's LED commands (pure logic).

``mobile_base/cmd_led`` (``UInt8MultiArray``): the driver reads six entries, 0 = off, anything
else = on: the red LEDs LED1, LED3, LED5, LED7 (our LED indices 0, 2, 4, 6), the body LED (8)
and the front LED (9).

``mobile_base/rgb_leds`` (``UInt8MultiArray``, 12 bytes): red, green, blue of LED2, LED4, LED6,
LED8 (our indices 1, 3, 5, 7), each 0..100 as the firmware takes them. An LED is on in
``led_state`` when any of its channels is non-zero; its colour goes to the rviz markers.

The driver reads its entries without checking the length (a short array is undefined
behaviour there); here a short array is refused with a message.
"""
LED_COMMAND_ENTRIES = 6
RED_LEDS = (0, 2, 4, 6, 8, 9)          # where cmd_led's six entries go
RGB_LEDS = (1, 3, 5, 7)                # where rgb_leds' four triples go
RGB_BYTES = 12
RGB_MAX = 100.0


def apply_led_command(current, values):
    """New LED states (10 values) from cmd_led's entries, or an error string."""
    if len(values) < LED_COMMAND_ENTRIES:
        return (f"cmd_led needs {LED_COMMAND_ENTRIES} entries (LED1, LED3, LED5, LED7, body, "
                f"front), got {len(values)}")
    state = [int(v) for v in current]
    for entry, led in zip(values[:LED_COMMAND_ENTRIES], RED_LEDS):
        state[led] = 0 if entry == 0 else 1
    return state


def apply_rgb_command(current, values):
    """(new LED states, {LED index: (r, g, b) in 0..1}) from rgb_leds, or an error string."""
    if len(values) != RGB_BYTES:
        return (f"rgb_leds needs exactly {RGB_BYTES} bytes (red, green, blue of LED2, LED4, "
                f"LED6, LED8), got {len(values)}")
    state = [int(v) for v in current]
    colours = {}
    for k, led in enumerate(RGB_LEDS):
        rgb = [min(float(v), RGB_MAX) / RGB_MAX for v in values[3 * k:3 * k + 3]]
        state[led] = 1 if any(rgb) else 0
        colours[led] = tuple(rgb)
    return state, colours

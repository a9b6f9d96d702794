"""The LED model (epuck/leds.py): states by robot name, all off for a new robot, each set stamped
with a change count, gone with the robot."""
import numpy as np

from epuck_vrep_compat.epuck.leds import LED_COUNT, RobotLeds


def test_new_robot_all_off_then_set_and_stamped():
    leds = RobotLeds()
    leds.add("ePuck0")
    values, stamp = leds.get("ePuck0")
    assert list(values) == [0] * LED_COUNT and stamp == 0 and leds.changes == 0
    assert leds.set("ePuck0", [1] * 9 + [0])
    values, stamp = leds.get("ePuck0")
    assert list(values) == [1] * 9 + [0] and stamp == leds.changes == 1
    values[0] = 0                      # a copy: the model is unchanged
    assert leds.get("ePuck0")[0][0] == 1


def test_unknown_or_removed_robot_is_refused():
    leds = RobotLeds()
    assert not leds.set("ePuck0", np.ones(LED_COUNT)) and leds.get("ePuck0") is None
    leds.add("ePuck0")
    leds.remove("ePuck0")
    assert not leds.set("ePuck0", np.ones(LED_COUNT)) and leds.changes == 0

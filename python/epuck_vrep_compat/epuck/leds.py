"""The e-pucks' LEDs as model state: what ``cmd_led`` last set, per robot.

Written by the LED command subscriber (a rospy thread), read by the LED face after each step;
a lock of its own keeps the two apart and makes a command that reads what it changes (a toggle)
whole (:meth:`RobotLeds.update`). Each change is stamped with a running change count, so a
reader that remembers the count it last saw knows at once whether to look again, and which
robots' LEDs were set since.
"""
import threading

import numpy as np

LED_COUNT = 10          # 8 ring + body + front (the driver's LED_NUMBER)


class RobotLeds:
    """LED states by robot name: ``LED_COUNT`` values (1 = on), all off for a new robot."""

    def __init__(self):
        self._lock = threading.Lock()
        self._states = {}          # robot name -> (values, change count at their last set)
        self.changes = 0           # counts every set since the start

    def add(self, name: str):
        with self._lock:
            self._states[name] = (np.zeros(LED_COUNT, dtype=np.uint8), 0)

    def remove(self, name: str):
        with self._lock:
            self._states.pop(name, None)

    def get(self, name: str):
        """(values (a copy), change count at their last set), or None for no such robot."""
        with self._lock:
            entry = self._states.get(name)
        return None if entry is None else (entry[0].copy(), entry[1])

    def update(self, name: str, change):
        """A command that reads what it changes (a toggle), whole: ``change(current values)``
        returns the new values, or a reason (str) to change nothing. Returns the new values,
        the reason, or None for no such robot."""
        with self._lock:
            entry = self._states.get(name)
            if entry is None:
                return None
            values = change(entry[0].copy())
            if not isinstance(values, str):
                self._set(name, values)
            return values

    def set(self, name: str, values) -> bool:
        """A robot's new LED states; False (nothing changes) when there is no such robot."""
        with self._lock:
            if name not in self._states:
                return False
            self._set(name, values)
            return True

    def _set(self, name: str, values):
        self.changes += 1
        self._states[name] = (np.array(values, dtype=np.uint8), self.changes)

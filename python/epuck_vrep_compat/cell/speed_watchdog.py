"""The speed scale's watchdog: a protective stop that does not depend on the supervisor.

ISO 10218 asks of a safety function that loses its input to stop the robot. The cell's robots
take a speed scale from a supervisor (``/<robot>/speed_scale``, through
:meth:`CellCommands.speed_scale`); when the watchdog is on for a robot and no scale has arrived
for longer than ``timeout_s`` of simulated time, the robot falls to scale 0 (it holds its
joints and base) until a fresh scale arrives, which then applies as it is. Simulated time, so
a run's outcome does not depend on how fast the machine steps it; a paused simulation never
times out. The clock of every watched robot starts when the watchdog is turned on and at every
reset: a supervisor has ``timeout_s`` to send its first scale.

ROS-free: the cell's face turns :attr:`stopped` into a topic and a log line.
"""
import math
from typing import Dict, Optional, Sequence


class SpeedScaleWatchdog:
    """Per watched robot, the simulated time of its last scale and whether it holds it."""

    def __init__(self):
        self.timeout_s = 0.0                  # 0: off
        self._robots: Optional[frozenset] = frozenset()   # None: every robot of the cell
        self._last: Dict[str, float] = {}
        self._start_s = 0.0
        self.stopped: Dict[str, bool] = {}    # robot -> held by the watchdog now

    def configure(self, timeout_s: float, robots: Optional[Sequence[str]], now_s: float):
        """Watch ``robots`` (None: every robot, also those loaded later) with ``timeout_s``
        (0 turns it off). ValueError for a negative or non-finite timeout."""
        if not (math.isfinite(timeout_s) and timeout_s >= 0.0):
            raise ValueError(f"speed scale timeout {timeout_s} must be >= 0 s (0 = off)")
        self.timeout_s = float(timeout_s)
        self._robots = None if robots is None else frozenset(robots)
        self.restart(now_s)

    def watches(self, robot: str) -> bool:
        return self.timeout_s > 0.0 and (self._robots is None or robot in self._robots)

    def restart(self, now_s: float):
        """Every clock from ``now_s``, nobody held (a reset, a new configuration)."""
        self._start_s = float(now_s)
        self._last.clear()
        self.stopped = {}

    def fresh(self, robot: str, now_s: float):
        """A scale arrived for ``robot`` (the caller applies it); the robot is no longer held."""
        self._last[robot] = float(now_s)
        self.stopped[robot] = False

    def check(self, arms, now_s: float):
        """Before the robots move in a step ending at ``now_s``: a watched robot whose last
        scale is older than the timeout falls to scale 0."""
        for arm in arms:
            name = arm.spec.name
            if not self.watches(name) or self.stopped.get(name, False):
                continue
            if now_s - self._last.get(name, self._start_s) > self.timeout_s + 1e-9:
                arm.set_speed_scale(0.0)
                self.stopped[name] = True

    def age_s(self, robot: str, now_s: float) -> float:
        """Simulated seconds since the robot's last scale (or since the watchdog's start)."""
        return now_s - self._last.get(robot, self._start_s)

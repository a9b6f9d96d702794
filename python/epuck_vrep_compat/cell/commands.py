"""Commands to the cell's robots, the one way in for the ROS faces (from rospy's threads):
joint targets, a mobile base's twist, the safety speed scale and its watchdog.

Each call takes the simulation lock (``Simulation.lock``, which every step holds), so one
command message lands whole between two steps and the last one wins. A call checks what it is
given and answers what it refused or changed, for the caller to warn about; a robot that is
gone ignores it. Clamping itself is the devices' (``devices/articulated.py``, ``arm_joint.py``).
"""
import math
from typing import NamedTuple, Optional

from epuck_vrep_compat.cell.devices.arm_joint import POSITION

UNKNOWN, NOT_FINITE, CLAMPED = "unknown", "not finite", "clamped"


class JointProblem(NamedTuple):
    """A joint command refused (UNKNOWN joint, NOT_FINITE value) or CLAMPED to ``limit``."""

    name: str
    value: float
    problem: str
    limit: Optional[float] = None


class CellCommands:
    """The command interface of one :class:`~epuck_vrep_compat.cell.cell.Cell`."""

    def __init__(self, cell):
        self._cell = cell

    def joints(self, robot: str, names, values, mode: str):
        """Target positions (``mode`` POSITION) or velocities (VELOCITY) of a robot's joints,
        pairwise by name; returns a :class:`JointProblem` for every joint refused (skipped, the
        others still move) or whose velocity was clamped to its limit."""
        problems = []
        with self._cell.sim.lock:
            arm = self._cell.arm_by_name.get(robot)
            if arm is None:
                return problems
            for name, value in zip(names, values):
                k = arm.movable_index(name)
                if k is None or not math.isfinite(value):
                    problems.append(JointProblem(name, value, UNKNOWN if k is None else NOT_FINITE))
                    continue
                joint = arm.joints[k]
                if mode == POSITION:
                    joint.set_target_position(value)
                elif joint.set_target_velocity(value) != value:
                    problems.append(JointProblem(name, value, CLAMPED, joint.max_velocity))
        return problems

    def twist(self, robot: str, vx: float, vy: float, wz: float):
        """A mobile base's twist (m/s, m/s, rad/s); returns the twist applied (scaled down to
        the base's top speed), or None when a value is not finite (refused)."""
        if not all(math.isfinite(x) for x in (vx, vy, wz)):
            return None
        with self._cell.sim.lock:
            arm = self._cell.arm_by_name.get(robot)
            return (vx, vy, wz) if arm is None else arm.set_twist(vx, vy, wz)

    def speed_scale(self, robot: str, scale: float):
        """The safety override of a robot's every motion (clamped to [0, 1] by the robot); a
        value that is not finite stops the robot (0, a protective stop: fail safe)."""
        with self._cell.sim.lock:
            arm = self._cell.arm_by_name.get(robot)
            if arm is not None:
                self._cell.watchdog.fresh(robot, self._cell.sim.time_s)
                arm.set_speed_scale(scale if math.isfinite(scale) else 0.0)

    def watch_speed_scale(self, timeout_s: float, robots=None):
        """Turn the speed scale's watchdog on (``timeout_s`` > 0) for ``robots`` (None: every
        robot, also those loaded later) or off (0); see :mod:`..speed_watchdog`. ValueError for
        a bad timeout or a robot the cell does not have."""
        with self._cell.sim.lock:
            unknown = sorted(set(robots or ()) - set(self._cell.arm_by_name))
            if unknown:
                raise ValueError(f"no cell robot named {', '.join(unknown)} (the cell has "
                                 f"{', '.join(sorted(self._cell.arm_by_name))})")
            self._cell.watchdog.configure(timeout_s, robots, self._cell.sim.time_s)

"""The movable joint of an articulated (URDF) robot as a component: V-REP's joint calls
(position, velocity, effort, targets, force) on one joint of an
:class:`~epuck_vrep_compat.cell.devices.articulated.ArticulatedRobot`.
"""
import math

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.devices.components import ComponentError, wrap_angle
from epuck_vrep_compat.geometry.urdf_kinematics import Joint

POSITION = "position"
VELOCITY = "velocity"
DEFAULT_EFFORT = 100.0        # N m or N, for a joint whose URDF gives no effort


class ArmJoint:
    """A movable joint of an articulated robot (V-REP: motor enabled, position control)."""

    mode = vc.JOINTMODE_FORCE

    def __init__(self, robot, index: int, urdf: Joint):
        self._robot = robot
        self.index = index                     # among the robot's movable joints
        self.name = urdf.name
        self.cyclic = urdf.joint_type == "continuous"
        self.prismatic = urdf.joint_type == "prismatic"
        self.joint_type = vc.JOINT_PRISMATIC if self.prismatic else vc.JOINT_REVOLUTE
        limits = urdf.limits
        self.lower, self.upper = limits.lower, limits.upper
        self.max_velocity = limits.velocity
        self.range_min = -math.pi if self.cyclic else self.lower
        self.range_span = -1.0 if self.cyclic else self.upper - self.lower
        # an explicit effort of 0 marks a passive joint (no motor), e.g. a mecanum roller
        self.max_force = limits.effort if math.isfinite(limits.effort) else DEFAULT_EFFORT
        self.rated_force = self.max_force      # what a stop (reset) gives back

    def position(self) -> float:
        q = float(self._robot.q[self.index])
        return wrap_angle(q) if self.cyclic else q

    def velocity(self) -> float:
        return float(self._robot.qd[self.index])

    def effort(self) -> float:
        return float(self._robot.tau[self.index])

    def _finite(self, what, value):
        if not math.isfinite(value):
            raise ComponentError(f"{what} {value} is not finite")

    def _clamped(self, value):
        return value if self.cyclic else min(max(value, self.lower), self.upper)

    def set_target_position(self, value: float):
        """A cyclic joint turns the shortest way to the angle (V-REP's), so its target stays
        within half a turn of where it is, however large the value asked."""
        self._finite("target position", value)
        if self.cyclic:
            q = float(self._robot.q[self.index])
            value = q + wrap_angle(value - q)
        self._robot.command(self.index, POSITION, self._clamped(value))

    def set_target_velocity(self, value: float) -> float:
        """Returns the velocity applied: the motor's limit (the URDF's) bounds it."""
        self._finite("target velocity", value)
        applied = min(max(value, -self.max_velocity), self.max_velocity)
        self._robot.command(self.index, VELOCITY, applied)
        return applied

    def set_position(self, value: float):
        """A cyclic joint's angle is taken modulo a turn (as V-REP's): pybullet's solver turns
        a joint standing at 1e308 rad into NaN for the whole robot once it moves."""
        self._finite("position", value)
        self._robot.reset_joint(self.index, wrap_angle(value) if self.cyclic
                                else self._clamped(value))

    def set_force(self, value: float):
        self._finite("force", value)
        if value < 0.0:
            raise ComponentError(f"force {value} is negative")
        self.max_force = value
        self._robot.dirty[self.index] = True

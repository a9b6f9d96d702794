"""The e-puck's own components: its wheel joints and IR cones, read from and driven through the
batched swarm of the core (its camera is a :class:`~epuck_vrep_compat.devices.components.
VisionSensor`, as every family's).

Frames follow V-REP where V-REP's services expose them: a proximity sensor's detection axis is
its z axis.
"""
import math

import numpy as np

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.devices.components import ComponentError, VisionSensor, wrap_angle


class WheelJoint:
    """A differential-drive wheel: a cyclic revolute joint in velocity (motor) mode."""

    joint_type = vc.JOINT_REVOLUTE
    mode = vc.JOINTMODE_FORCE
    cyclic = True
    range_min = -math.pi
    range_span = -1.0          # V-REP's "cyclic" marker

    def __init__(self, epucks, robot_name: str, column: int):
        self._epucks = epucks       # the EpuckRobots
        self._robot = robot_name
        self._column = column
        self.max_force = 0.0

    def position(self) -> float:
        row = self._epucks.robot_index(self._robot)
        return wrap_angle(float(self._epucks.swarm.wheel_angles[row, self._column]))

    def velocity(self) -> float:
        return float(self._epucks.swarm.wheel_speeds[self._epucks.robot_index(self._robot),
                                                     self._column])

    def effort(self) -> float:
        return 0.0              # kinematic drive: no torque is computed

    def set_target_velocity(self, value: float):
        if not math.isfinite(value):
            raise ComponentError(f"target velocity {value} is not finite")
        self._epucks.set_wheel_speed(self._robot, self._column, value)

    def set_position(self, value: float):
        raise ComponentError("a wheel joint is driven by velocity; its position cannot be set")

    def set_target_position(self, value: float):
        raise ComponentError("a wheel joint is in velocity mode; it has no target position")

    def set_force(self, value: float):
        if not math.isfinite(value):
            raise ComponentError(f"force {value} is not finite")
        self.max_force = value


class ConeProximity:
    """One IR cone of a robot, read from the core's last step (V-REP's sensor frame: z = axis)."""

    subtype = vc.PROXSENSOR_CONE

    def __init__(self, epucks, robot_name: str, sensor_index: int):
        self._epucks = epucks       # the EpuckRobots
        self._robot = robot_name
        self._sensor = sensor_index

    def read(self):
        """(detection state 0/1, point (3), detected object handle or -1, surface normal (3)).
        An object removed since the last step is not reported."""
        swarm = self._epucks.swarm
        row = self._epucks.robot_index(self._robot)
        handle = int(swarm.detected_handles[row, self._sensor])
        if handle < 0 or handle not in self._epucks.sim.registry:
            return 0, np.zeros(3), -1, np.zeros(3)
        return (1, _core_to_vrep(swarm.detected_points[row, self._sensor]), handle,
                _core_to_vrep(swarm.detected_normals[row, self._sensor]))


def _core_to_vrep(v):
    """Core sensor frame (x along the beam, z up) to V-REP's (z along the beam)."""
    x, y, z = v
    return np.array([-z, y, x])



def attach_components(epucks, name: str, parts):
    """Give a new e-puck's registry objects (``parts``, a ``RobotParts`` of robot ``name`` of
    ``epucks``, the EpuckRobots) their behaviour: its two wheel joints, its IR cones and its
    camera."""
    for column, side in enumerate(("left", "right")):
        parts.parts[f"{side}Joint"].properties["joint"] = WheelJoint(epucks, name, column)
    for k in range(len(epucks.model.sensors)):
        parts.parts[f"proxSensor{k}"].properties["proximity"] = ConeProximity(epucks, name, k)
    parts.parts["camera"].properties["vision"] = VisionSensor(
        epucks.sim, parts.handle("camera"), epucks.camera, ignore_handle=parts.root.handle)


__all__ = ["ConeProximity", "WheelJoint", "attach_components"]

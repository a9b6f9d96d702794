"""Components attached to scene objects: what a joint, a proximity sensor or a vision sensor
*does*, behind one small interface each, so the ROS faces and the ``/vrep`` services read and
drive any object the same way, whatever model it belongs to.

Frames follow V-REP where V-REP's services expose them: a proximity sensor's detection axis is
its z axis; a vision sensor looks along its z axis with y up.
"""
import math
from dataclasses import dataclass

import numpy as np

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import quat_mul


class ComponentError(ValueError):
    """An operation this object does not support; the message says why (V-REP's -1)."""


@dataclass
class CameraSpec:
    """A vision sensor's image size, rate, field of view and clipping planes."""
    # The real e-puck's typical colour acquisition: 40 x 40 sub-sampled at about 4 frames/s.
    width: int = 40
    height: int = 40
    rate_hz: float = 4.0
    vertical_fov_rad: float = 0.84       # Webots' e-puck camera field of view
    near_m: float = 0.005
    far_m: float = 2.0


def wrap_angle(a: float) -> float:
    """To (-pi, pi], as V-REP reports cyclic revolute joints."""
    return math.pi - math.fmod(math.pi - a, 2.0 * math.pi) if a <= -math.pi or a > math.pi else a


class WheelJoint:
    """A differential-drive wheel: a cyclic revolute joint in velocity (motor) mode."""

    joint_type = vc.JOINT_REVOLUTE
    mode = vc.JOINTMODE_FORCE
    cyclic = True
    range_min = -math.pi
    range_span = -1.0          # V-REP's "cyclic" marker

    def __init__(self, sim, robot_name: str, column: int):
        self._sim = sim
        self._robot = robot_name
        self._column = column
        self.max_force = 0.0

    def position(self) -> float:
        row = self._sim.robot_index(self._robot)
        return wrap_angle(float(self._sim.swarm.wheel_angles[row, self._column]))

    def velocity(self) -> float:
        return float(self._sim.swarm.wheel_speeds[self._sim.robot_index(self._robot),
                                                  self._column])

    def effort(self) -> float:
        return 0.0              # kinematic drive: no torque is computed

    def set_target_velocity(self, value: float):
        if not math.isfinite(value):
            raise ComponentError(f"target velocity {value} is not finite")
        self._sim.set_wheel_speed(self._robot, self._column, value)

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

    def __init__(self, sim, robot_name: str, sensor_index: int):
        self._sim = sim
        self._robot = robot_name
        self._sensor = sensor_index

    def read(self):
        """(detection state 0/1, point (3), detected object handle or -1, surface normal (3)).
        An object removed since the last step is not reported."""
        swarm = self._sim.swarm
        row = self._sim.robot_index(self._robot)
        handle = int(swarm.detected_handles[row, self._sensor])
        if handle < 0 or handle not in self._sim.registry:
            return 0, np.zeros(3), -1, np.zeros(3)
        return (1, _core_to_vrep(swarm.detected_points[row, self._sensor]), handle,
                _core_to_vrep(swarm.detected_normals[row, self._sensor]))


def _core_to_vrep(v):
    """Core sensor frame (x along the beam, z up) to V-REP's (z along the beam)."""
    x, y, z = v
    return np.array([-z, y, x])


# A V-REP vision sensor looks along its z axis with y up; the core's camera looks along x with
# z up. The core camera's orientation is the vision sensor's times this fixed rotation.
VISION_TO_CAMERA = np.array([-0.5, -0.5, -0.5, 0.5])    # camera x = vision z, y = x, z = y


class VisionSensor:
    """A pinhole camera rendered by the core's ray-cast renderer from its object's pose."""

    def __init__(self, sim, handle: int, spec: CameraSpec, ignore_handle: int = -1):
        self._sim = sim
        self.handle = handle
        self.spec = spec
        self._ignore = ignore_handle

    @property
    def resolution(self):
        return self.spec.width, self.spec.height

    def camera_pose(self):
        position, quat = self._sim.registry.world_pose(self.handle)
        return position, quat_mul(quat, VISION_TO_CAMERA)

    @property
    def ignore_handle(self) -> int:
        """The object the camera does not see (the robot carrying it), or -1."""
        return self._ignore

    def render(self):
        """(rgb uint8 (H, W, 3) top row first, depth float32 (H, W) metres along the axis)."""
        position, quat = self.camera_pose()
        s = self.spec
        return self._sim.world.render(position, quat, s.width, s.height, s.vertical_fov_rad,
                                      s.near_m, s.far_m, self._ignore)


__all__ = ["CameraSpec", "ComponentError", "ConeProximity", "VisionSensor", "WheelJoint",
           "wrap_angle"]

"""Components attached to scene objects: what a joint, a proximity sensor or a vision sensor
*does*, behind one small interface each, so the ROS faces and the ``/vrep`` services read and
drive any object the same way, whatever model it belongs to. Here is what every robot family
shares (the error, the angle wrap, the vision sensor); a family's own components are in its
package (:mod:`epuck_vrep_compat.epuck.components`, :mod:`epuck_vrep_compat.cell.devices`).

Frames follow V-REP where V-REP's services expose them: a vision sensor looks along its z axis
with y up.
"""
import math
from dataclasses import dataclass

import numpy as np

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
    """To (-pi, pi], as V-REP reports cyclic revolute joints; exactly ``a`` when it is there
    already (IEEE remainder, exact for any finite ``a``)."""
    r = math.remainder(float(a), 2.0 * math.pi)
    return math.pi if r <= -math.pi else r


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
        self._kept_depth = None

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

    def view(self):
        """The core renderer's arguments for this camera now: pose, intrinsics, clipping,
        ignore handle (and, for a sensor that has one, its render mask)."""
        position, quat = self.camera_pose()
        s = self.spec
        return (position, quat, s.width, s.height, s.vertical_fov_rad, s.near_m, s.far_m,
                self._ignore)

    def render(self):
        """(rgb uint8 (H, W, 3) top row first, depth float32 (H, W) metres along the axis)."""
        return self._sim.world.render(*self.view())

    def render_depth(self, out=None):
        """render()'s depth alone, bit for bit; cheaper (no colours shaded). ``out``: a float32
        (H, W) array to render it into and return, instead of a new one."""
        return self._sim.world.render(*self.view(), rgb=False, depth_out=out)[1]

    def render_depth_kept(self):
        """render_depth() into a buffer the sensor keeps, valid until the sensor renders into
        it again (every reading is made under the simulation's lock): for a reading computed
        from it at once, as V-REP's depth buffer, without a new image's memory each time (a
        640 x 480 image is 1.2 MB, mapped and unmapped on its own in the simulator)."""
        shape = (self.spec.height, self.spec.width)
        if self._kept_depth is None or self._kept_depth.shape != shape:
            self._kept_depth = np.empty(shape, np.float32)
        return self.render_depth(out=self._kept_depth)

    def render_rgb(self):
        """render()'s colour image alone, bit for bit."""
        return self._sim.world.render(*self.view(), depth=False)[0]


__all__ = ["VISION_TO_CAMERA", "CameraSpec", "ComponentError", "VisionSensor", "wrap_angle"]

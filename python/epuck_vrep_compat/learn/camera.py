"""The robots' cameras in the learning worlds, drawn by the function that draws the simulator's
(:func:`epuck_vrep_compat.epuck.cameras.render_cameras`: the camera poses composed from
the robots' poses and the camera's mount, one core render call per world) with the e-puck
model's camera mount (:func:`epuck_vrep_compat.scene.epuck_model.register_epuck`) and a
``CameraSpec``: for the same world state an image here is the one the ROS camera topic carries
(rgb8; the drivers' mono8 is its luma). Nothing is rendered unless a layout asks for the camera
block (it costs a ray per pixel).

The learning worlds have no floor: the camera row (the image's middle rows, at the horizon)
of the profiles' default cameras meets walls, cylinders and robots in a walled 1 m arena and
would reach the floor only beyond the camera's 2 m range.
"""
from typing import Optional

import numpy as np

from epuck_vrep_compat._core import BatchedWorlds
from epuck_vrep_compat.devices.components import CameraSpec
from epuck_vrep_compat.epuck.cameras import render_cameras
from epuck_vrep_compat.scene.epuck_model import register_epuck
from epuck_vrep_compat.scene.registry import SceneRegistry


def camera_mount(model):
    """The e-puck's camera part of the scene model (its ``local_position`` and ``local_quat``
    on the robot), as the simulator registers it for every robot."""
    parts = register_epuck(SceneRegistry(), model, 0, "epuck", None, lambda: np.zeros(2))
    return parts.parts["camera"]


class WorldCameras:
    """The cameras of every robot of a ``BatchedWorlds`` (``core``), with ``spec`` (the
    e-puck's default ``CameraSpec()`` when None: the ``vrep`` profile's 40 x 40)."""

    def __init__(self, core, model, spec: Optional[CameraSpec] = None):
        self.core = core
        self.spec = spec if spec is not None else CameraSpec()
        mount = camera_mount(model)
        robots = core.robots
        self._mount_positions = np.tile(mount.local_position, (robots, 1))
        self._mount_quats = np.tile(mount.local_quat, (robots, 1))
        self._ignore = [BatchedWorlds.ROBOT_HANDLE_BASE + r for r in range(robots)]

    def render(self, poses) -> np.ndarray:
        """rgb8 images (N, H, W, 3) of every robot (rows ``world * R + robot``) at ``poses``
        (N, 3), the core's ground truth of this step."""
        robots, s = self.core.robots, self.spec
        out = np.empty((self.core.size, s.height, s.width, 3), np.uint8)
        for b in range(self.core.worlds):
            rows = slice(b * robots, (b + 1) * robots)
            out[rows] = render_cameras(self.core.collision_world(b), s, np.asarray(poses[rows]),
                                       self._mount_positions, self._mount_quats, self._ignore)
        return out

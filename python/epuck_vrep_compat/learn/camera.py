"""The robots' cameras in the learning worlds, drawn by the function that draws the simulator's
(:func:`epuck_vrep_compat.epuck.cameras.render_robot_cameras`: the camera poses composed from
the robots' poses and the camera's mount, one core render call per world) with the e-puck
model's camera mount (:func:`epuck_vrep_compat.scene.epuck_model.register_epuck`) and a
``CameraSpec``: for the same world state an image here is the one the ROS camera topic carries
(rgb8; the drivers' mono8 is its luma). Nothing is rendered unless a layout asks for the camera
block (it costs a ray per pixel).

The learning worlds have no floor: the camera row (the image's middle rows, at the horizon)
of the profiles' default cameras meets walls, cylinders and robots in a walled 1 m arena and
would reach the floor only beyond the camera's 2 m range.
"""
from types import SimpleNamespace
from typing import Optional

import numpy as np

from epuck_vrep_compat._core import BatchedWorlds
from epuck_vrep_compat.devices.components import CameraSpec
from epuck_vrep_compat.epuck.cameras import render_robot_cameras
from epuck_vrep_compat.scene.epuck_model import register_epuck
from epuck_vrep_compat.scene.registry import SceneRegistry


def camera_mount(model):
    """The e-puck's camera part of the scene model (its ``local_position`` and ``local_quat``
    on the robot), as the simulator registers it for every robot."""
    parts = register_epuck(SceneRegistry(), model, 0, "epuck", None, lambda: np.zeros(2))
    return parts.parts["camera"]


class _WorldRobots:
    """One world's robots as ``render_robot_cameras`` reads the simulator's ``EpuckRobots``:
    ``camera`` (the spec), ``robot_index`` (here the robot's index), ``robots[r].parts``'s
    camera mount and the body it ignores, ``swarm.poses``, ``sim.world``."""

    def __init__(self, spec, robots, poses, world):
        self.camera, self.robots = spec, robots
        self.swarm = SimpleNamespace(poses=poses)
        self.sim = SimpleNamespace(world=world)

    @staticmethod
    def robot_index(robot: int) -> int:
        return robot


class WorldCameras:
    """The cameras of every robot of a ``BatchedWorlds`` (``core``), with ``spec`` (the
    e-puck's default ``CameraSpec()`` when None: the ``vrep`` profile's 40 x 40)."""

    def __init__(self, core, model, spec: Optional[CameraSpec] = None):
        self.core = core
        self.spec = spec if spec is not None else CameraSpec()
        mount = camera_mount(model)
        self._robots = [SimpleNamespace(parts={"camera": SimpleNamespace(
            local_position=mount.local_position, local_quat=mount.local_quat,
            properties={"vision": SimpleNamespace(
                ignore_handle=BatchedWorlds.ROBOT_HANDLE_BASE + r)})})
            for r in range(core.robots)]

    def render(self, poses) -> np.ndarray:
        """rgb8 images (N, H, W, 3) of every robot (rows ``world * R + robot``) at ``poses``
        (N, 3), the core's ground truth of this step."""
        robots, s = self.core.robots, self.spec
        out = np.empty((self.core.size, s.height, s.width, 3), np.uint8)
        indices = list(range(robots))
        for b in range(self.core.worlds):
            rows = slice(b * robots, (b + 1) * robots)
            view = _WorldRobots(s, self._robots, np.asarray(poses[rows]),
                                self.core.collision_world(b))
            out[rows] = render_robot_cameras(view, indices)
        return out

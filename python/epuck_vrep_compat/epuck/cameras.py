"""The robots' cameras rendered together: one call of the core's renderer for a step's images.

A camera rendered alone (``VisionSensor.render``) composes its pose along the registry's parent
chain in Python; a step at 1000 robots renders some 200 of them. Here their poses are composed
for all robots at once, in the same arithmetic, from the swarm's poses and each camera's mount
on its robot (a robot's parts are rigid: ``EpuckRobots.move_object`` refuses to move one), and
the images are drawn in one core call without the interpreter lock.
"""
from typing import Sequence

import numpy as np

from epuck_vrep_compat.devices.components import VISION_TO_CAMERA
from epuck_vrep_compat.geometry.transforms import compose, quat_from_yaw, quat_mul


def render_robot_cameras(epucks, names: Sequence[str], threads: int = 1) -> np.ndarray:
    """The colour images (K, H, W, 3) uint8 of the named robots' cameras of ``epucks`` (the
    ``EpuckRobots``), each equal to its ``VisionSensor.render``, on up to ``threads`` threads."""
    rows = [epucks.robot_index(n) for n in names]
    mounts = [epucks.robots[r].parts["camera"] for r in rows]
    return render_cameras(epucks.sim.world, epucks.camera, epucks.swarm.poses[rows],
                          [m.local_position for m in mounts], [m.local_quat for m in mounts],
                          [m.properties["vision"].ignore_handle for m in mounts], threads)


def render_cameras(world, spec, poses, mount_positions, mount_quats, ignore_handles,
                   threads: int = 1) -> np.ndarray:
    """The colour images (K, H, W, 3) uint8 of K cameras (``spec``, a ``CameraSpec``) mounted
    at (``mount_positions``, ``mount_quats``) on robots standing at ``poses`` (K, 3: x, y,
    yaw) in the collision ``world``, each not seeing its ``ignore_handles`` entry (its own
    body): the simulator's robots and the learning worlds' alike."""
    if len(poses) == 0:
        return np.zeros((0, spec.height, spec.width, 3), np.uint8)
    x, y, yaw = np.asarray(poses, dtype=float).T
    root_position = np.column_stack((x, y, np.zeros(len(x))))
    position, quat = compose(root_position, quat_from_yaw(yaw),
                             np.asarray(mount_positions, dtype=float).reshape(-1, 3),
                             np.asarray(mount_quats, dtype=float).reshape(-1, 4))
    return world.render_rgb_batch(position, quat_mul(quat, VISION_TO_CAMERA), spec.width,
                                  spec.height, spec.vertical_fov_rad, spec.near_m, spec.far_m,
                                  list(ignore_handles), threads=threads)

"""The arena of a scene as static objects: the floor, four walls and the obstacles, each
registered under its name (``Floor``, ``Wall0``..``Wall3``, the obstacle's) and added to the
collision world under the same handle."""
from typing import List, Tuple

import numpy as np

from epuck_vrep_compat._core import GROUP_FLOOR, GROUP_STATIC
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import quat_from_yaw
from epuck_vrep_compat.scene.scene_file import Obstacle

FLOOR_THICKNESS_M = 0.01


def build_arena(scene, registry, world) -> List[Tuple[Obstacle, int]]:
    """Registers the arena; returns each obstacle with its handle."""
    arena = scene.arena
    sx, sy = arena.size_m
    h, t = arena.wall_height_m, arena.wall_thickness_m
    _add_box(registry, world, arena.floor_name, (sx + 2 * t, sy + 2 * t, FLOOR_THICKNESS_M),
             (0.0, 0.0, -0.5 * FLOOR_THICKNESS_M), 0.0, arena.floor_color, GROUP_FLOOR)
    walls = (((sx + 2 * t, t, h), (0.0, 0.5 * (sy + t))),
             ((sx + 2 * t, t, h), (0.0, -0.5 * (sy + t))),
             ((t, sy, h), (0.5 * (sx + t), 0.0)),
             ((t, sy, h), (-0.5 * (sx + t), 0.0)))
    for k, (size, (x, y)) in enumerate(walls):
        _add_box(registry, world, f"Wall{k}", size, (x, y, 0.5 * h), 0.0, arena.wall_color,
                 GROUP_STATIC)
    obstacles = []
    for o in scene.obstacles:
        x, y = o.position_m
        if o.shape == "box":
            obj = _add_box(registry, world, o.name, o.size_m, (x, y, 0.5 * o.size_m[2]),
                           o.yaw_rad, o.color, GROUP_STATIC)
        else:
            quat = quat_from_yaw(o.yaw_rad)
            size = (2.0 * o.radius_m, 2.0 * o.radius_m, o.height_m)
            obj = registry.add(o.name, vc.OBJECT_SHAPE, vc.WORLD, (x, y, 0.5 * o.height_m), quat,
                               properties=dict(shape="cylinder", size=size, color=o.color))
            world.add_cylinder(obj.handle, o.radius_m, o.height_m, obj.local_position, quat,
                               o.color, GROUP_STATIC)
        obstacles.append((o, obj.handle))
    return obstacles


def _add_box(registry, world, name, size, position, yaw, color, group):
    quat = quat_from_yaw(yaw)
    obj = registry.add(name, vc.OBJECT_SHAPE, vc.WORLD, position, quat,
                       properties=dict(shape="box", size=tuple(size), color=color))
    world.add_box(obj.handle, 0.5 * np.asarray(size, dtype=float),
                  np.asarray(position, dtype=float), quat, color, group)
    return obj

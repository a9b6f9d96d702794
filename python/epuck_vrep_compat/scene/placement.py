"""Where robots stand: the start poses of a scene's robots (its listed ones first, then a free
grid), and a free place for a robot added while the simulation runs."""
import math
from typing import List, Sequence, Tuple

import numpy as np

from epuck_vrep_compat.scene.scene_file import Obstacle, Scene, SceneError

CLEARANCE_M = 0.02     # free gap kept around each placed robot


def place_robots(scene: Scene, count: int,
                 body_radius_m: float) -> List[Tuple[float, float, float]]:
    """``count`` poses (x, y, yaw) that fit in the arena without touching anything.

    Raises SceneError when they do not fit (the caller names the parameter ``n``).
    """
    poses = [(r.position_m[0], r.position_m[1], r.yaw_rad) for r in scene.robots[:count]]
    for x, y, _ in poses:
        if not _free(scene, scene.obstacles, (), x, y, body_radius_m):
            raise SceneError(f"robot start ({x}, {y}) overlaps the arena wall or an obstacle")
    for x, y in zip(*_grid(scene, body_radius_m)):
        if len(poses) >= count:
            return poses
        if _free(scene, scene.obstacles, [p[:2] for p in poses], x, y, body_radius_m):
            poses.append((x, y, 0.0))
    if len(poses) < count:
        raise SceneError(f"only {len(poses)} robots fit in a {scene.arena.size_m[0]} x "
                         f"{scene.arena.size_m[1]} m arena, {count} asked for")
    return poses


def free_place(scene: Scene, obstacles: Sequence[Obstacle], occupied_xy, body_radius_m: float,
               near_xy=(0.0, 0.0)) -> Tuple[float, float]:
    """The point of the start grid nearest to ``near_xy`` where a robot touches neither the
    walls, the given obstacles, nor a robot standing at one of ``occupied_xy`` (ties go to
    the grid's order). Raises SceneError when the arena is full."""
    xs, ys = _grid(scene, body_radius_m)
    order = np.argsort(np.hypot(np.subtract(xs, near_xy[0]), np.subtract(ys, near_xy[1])),
                       kind="stable")
    occupied = np.asarray(occupied_xy, dtype=float).reshape(-1, 2)
    for k in order.tolist():
        if _free(scene, obstacles, occupied, xs[k], ys[k], body_radius_m):
            return float(xs[k]), float(ys[k])
    raise SceneError(f"no free place left for a robot in the {scene.arena.size_m[0]} x "
                     f"{scene.arena.size_m[1]} m arena")


def _grid(scene, r):
    """x and y of the start grid's points, row by row from the (-x, -y) corner."""
    spacing = 2.0 * r + 2.0 * CLEARANCE_M
    half_x = 0.5 * scene.arena.size_m[0] - r - CLEARANCE_M
    half_y = 0.5 * scene.arena.size_m[1] - r - CLEARANCE_M
    nx = max(0, int(math.floor(2.0 * half_x / spacing)) + 1)
    ny = max(0, int(math.floor(2.0 * half_y / spacing)) + 1)
    y, x = np.meshgrid(-half_y + spacing * np.arange(ny), -half_x + spacing * np.arange(nx),
                       indexing="ij")
    return x.ravel().tolist(), y.ravel().tolist()


def _free(scene, obstacles, occupied_xy, x, y, r) -> bool:
    half_x, half_y = 0.5 * scene.arena.size_m[0], 0.5 * scene.arena.size_m[1]
    if abs(x) > half_x - r or abs(y) > half_y - r:
        return False
    for o in obstacles:
        ox, oy = o.position_m
        if math.hypot(x - ox, y - oy) < o.footprint_radius_m() + r + CLEARANCE_M:
            return False
    occupied = np.asarray(occupied_xy, dtype=float).reshape(-1, 2)
    if len(occupied) == 0:
        return True
    return bool(np.hypot(occupied[:, 0] - x, occupied[:, 1] - y).min() >= 2.0 * r + CLEARANCE_M)

"""Start poses: the scene's listed robots first, then a free grid for the rest."""
import math
from typing import List, Tuple

from epuck_vrep_compat.scene.scene_file import Scene, SceneError

CLEARANCE_M = 0.02     # free gap kept around each placed robot


def place_robots(scene: Scene, count: int,
                 body_radius_m: float) -> List[Tuple[float, float, float]]:
    """``count`` poses (x, y, yaw) that fit in the arena without touching anything.

    Raises SceneError when they do not fit (the caller names the parameter ``n``).
    """
    poses = [(r.position_m[0], r.position_m[1], r.yaw_rad) for r in scene.robots[:count]]
    for x, y, _ in poses:
        if not _free(scene, poses, x, y, body_radius_m, check_robots=False):
            raise SceneError(f"robot start ({x}, {y}) overlaps the arena wall or an obstacle")
    spacing = 2.0 * body_radius_m + 2.0 * CLEARANCE_M
    half_x = 0.5 * scene.arena.size_m[0] - body_radius_m - CLEARANCE_M
    half_y = 0.5 * scene.arena.size_m[1] - body_radius_m - CLEARANCE_M
    nx = max(0, int(math.floor(2.0 * half_x / spacing)) + 1)
    ny = max(0, int(math.floor(2.0 * half_y / spacing)) + 1)
    for j in range(ny):
        for i in range(nx):
            if len(poses) >= count:
                return poses
            x = -half_x + i * spacing
            y = -half_y + j * spacing
            if _free(scene, poses, x, y, body_radius_m):
                poses.append((x, y, 0.0))
    if len(poses) < count:
        raise SceneError(f"only {len(poses)} robots fit in a {scene.arena.size_m[0]} x "
                         f"{scene.arena.size_m[1]} m arena, {count} asked for")
    return poses


def _free(scene, poses, x, y, r, check_robots=True) -> bool:
    half_x, half_y = 0.5 * scene.arena.size_m[0], 0.5 * scene.arena.size_m[1]
    if abs(x) > half_x - r or abs(y) > half_y - r:
        return False
    for o in scene.obstacles:
        ox, oy = o.position_m
        if math.hypot(x - ox, y - oy) < o.footprint_radius_m() + r + CLEARANCE_M:
            return False
    if check_robots:
        for px, py, _ in poses:
            if math.hypot(x - px, y - py) < 2.0 * r + CLEARANCE_M:
                return False
    return True

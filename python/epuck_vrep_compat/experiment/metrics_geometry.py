"""The plane geometry of the experiment metrics, numpy only: a scene's walls and obstacles as
2-D shapes, a robot disk's clearance to them, contact onsets, grid coverage and target regions.

Lengths are metres, angles radians, in the scene's (``odom``) frame. The scene is the parsed
scene YAML (``worlds/arena.yaml``'s format) with the defaults of ``scene/scene_file.py`` for
missing keys, so an empty scene is the default 1 m x 1 m arena. As ``sim/arena.py`` builds it,
the walls stand outside the arena: their inner faces are at x = ±size_x/2, y = ±size_y/2.
A clearance is the gap between a robot's disk and a shape (negative when they overlap).
"""
import math
from dataclasses import dataclass

import numpy as np

EPUCK_RADIUS_M = 0.037          # body radius: Enki, Webots and the simulator's EpuckModel
# scene_file.py's defaults for keys a scene leaves out
DEFAULT_ARENA_SIZE_M = (1.0, 1.0)
DEFAULT_WALL_THICKNESS_M = 0.01
DEFAULT_BOX_SIZE_M = (0.1, 0.1)
DEFAULT_CYLINDER_RADIUS_M = 0.03


@dataclass
class Shapes2D:
    """A scene's footprint: oriented rectangles (walls first, then box obstacles) and discs."""

    box_center_m: np.ndarray       # (B, 2)
    box_half_m: np.ndarray         # (B, 2) half extents along the box's own x and y
    box_yaw_rad: np.ndarray        # (B,)
    box_is_wall: np.ndarray        # (B,) bool
    disc_center_m: np.ndarray      # (C, 2) cylinder obstacles
    disc_radius_m: np.ndarray      # (C,)


def arena_size_m(world: dict) -> tuple:
    """The arena's inner (x, y) size [m] (the default when the scene gives none)."""
    size = (world.get("arena") or {}).get("size_m", DEFAULT_ARENA_SIZE_M)
    return float(size[0]), float(size[1])


def shapes_of(world: dict) -> Shapes2D:
    """The four walls and the obstacles of a parsed scene file; raises ValueError on an
    obstacle of unknown shape or without a position."""
    sx, sy = arena_size_m(world)
    t = float((world.get("arena") or {}).get("wall_thickness_m", DEFAULT_WALL_THICKNESS_M))
    # the walls as sim/arena.py places them: x walls span the corners, y walls fit between
    boxes = [((0.0, 0.5 * (sy + t)), (sx + 2 * t, t), 0.0, True),
             ((0.0, -0.5 * (sy + t)), (sx + 2 * t, t), 0.0, True),
             ((0.5 * (sx + t), 0.0), (t, sy), 0.0, True),
             ((-0.5 * (sx + t), 0.0), (t, sy), 0.0, True)]
    discs = []
    for i, o in enumerate(world.get("obstacles") or []):
        if "position_m" not in o:
            raise ValueError(f"scene obstacles[{i}] has no position_m")
        xy = (float(o["position_m"][0]), float(o["position_m"][1]))
        if o.get("shape") == "box":
            size = o.get("size_m", DEFAULT_BOX_SIZE_M)
            boxes.append((xy, (float(size[0]), float(size[1])), float(o.get("yaw_rad", 0.0)),
                          False))
        elif o.get("shape") == "cylinder":
            discs.append((xy, float(o.get("radius_m", DEFAULT_CYLINDER_RADIUS_M))))
        else:
            raise ValueError(f"scene obstacles[{i}] has shape {o.get('shape')!r}")
    return Shapes2D(
        box_center_m=np.array([b[0] for b in boxes], dtype=float).reshape(-1, 2),
        box_half_m=0.5 * np.array([b[1] for b in boxes], dtype=float).reshape(-1, 2),
        box_yaw_rad=np.array([b[2] for b in boxes], dtype=float),
        box_is_wall=np.array([b[3] for b in boxes], dtype=bool),
        disc_center_m=np.array([d[0] for d in discs], dtype=float).reshape(-1, 2),
        disc_radius_m=np.array([d[1] for d in discs], dtype=float))


def _box_distance(xy, center, half, yaw):
    """Signed distance [m] of points (T, 2) to one oriented rectangle (negative inside)."""
    c, s = math.cos(yaw), math.sin(yaw)
    d = xy - center
    local = np.abs(np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=1))
    q = local - half
    outside = np.hypot(np.maximum(q[:, 0], 0.0), np.maximum(q[:, 1], 0.0))
    return outside + np.minimum(np.maximum(q[:, 0], q[:, 1]), 0.0)


def clearances(shapes: Shapes2D, xy: np.ndarray, radius_m: float = EPUCK_RADIUS_M):
    """(wall, obstacle) clearance [m] of a robot disk at each of ``xy`` (T, 2): the smallest
    gap to any wall, to any obstacle (+inf when the scene has none)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    wall = np.full(len(xy), np.inf)
    obstacle = np.full(len(xy), np.inf)
    for center, half, yaw, is_wall in zip(shapes.box_center_m, shapes.box_half_m,
                                          shapes.box_yaw_rad, shapes.box_is_wall):
        gap = _box_distance(xy, center, half, yaw) - radius_m
        if is_wall:
            wall = np.minimum(wall, gap)
        else:
            obstacle = np.minimum(obstacle, gap)
    for center, radius in zip(shapes.disc_center_m, shapes.disc_radius_m):
        gap = np.hypot(xy[:, 0] - center[0], xy[:, 1] - center[1]) - radius - radius_m
        obstacle = np.minimum(obstacle, gap)
    return wall, obstacle


def pair_distances(xy: np.ndarray):
    """Centre-to-centre distances [m] of robots (R, T, 2) at common instants: yields
    ``((i, j), (T,) distances)`` for every pair i < j, one at a time (R² / 2 pairs of a long
    run would not fit in memory together)."""
    r = xy.shape[0]
    for i in range(r):
        for j in range(i + 1, r):
            yield (i, j), np.hypot(xy[i, :, 0] - xy[j, :, 0], xy[i, :, 1] - xy[j, :, 1])


def onsets(contact: np.ndarray) -> int:
    """How many times ``contact`` (T,) turns from False to True. Contact at the first instant
    is not an onset: the robot did not enter it during the recording."""
    c = np.asarray(contact, dtype=bool)
    return int(np.count_nonzero(c[1:] & ~c[:-1]))


def held_time_s(t: np.ndarray, flag: np.ndarray) -> float:
    """Time [s] that ``flag`` holds, each instant's value held until the next instant (the last
    instant adds nothing)."""
    flag = np.asarray(flag, dtype=bool)
    return float(np.sum(np.diff(t)[flag[:-1]])) if len(t) > 1 else 0.0


def coverage_fraction(world: dict, xy: np.ndarray, cell_m: float,
                      radius_m: float = EPUCK_RADIUS_M) -> float:
    """The fraction of the arena's grid cells whose centre lies within ``radius_m`` of one of the
    points ``xy`` (N, 2). The grid has round(size / cell_m) cells a side (at least one), so its
    cells tile the arena exactly and are as near ``cell_m`` wide as that allows."""
    sx, sy = arena_size_m(world)
    nx, ny = max(1, round(sx / cell_m)), max(1, round(sy / cell_m))
    wx, wy = sx / nx, sy / ny
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    px, py = xy[:, 0], xy[:, 1]
    col = np.floor((px + 0.5 * sx) / wx).astype(int)
    row = np.floor((py + 0.5 * sy) / wy).astype(int)
    covered = np.zeros((nx, ny), dtype=bool)
    r2 = radius_m * radius_m
    # a point covers only cells up to ceil(r / w) from its own (their centres are at least
    # (k - 1/2) w away); one pass per offset keeps the arrays one value a point (a
    # point-by-cell matrix is slow and large)
    kx, ky = int(math.ceil(radius_m / wx)), int(math.ceil(radius_m / wy))
    for dx in range(-kx, kx + 1):
        ix = col + dx
        dx2 = (-0.5 * sx + (ix + 0.5) * wx - px) ** 2
        near = (ix >= 0) & (ix < nx) & (dx2 <= r2)
        ix, dx2, near_row, near_y = ix[near], dx2[near], row[near], py[near]
        for dy in range(-ky, ky + 1):
            iy = near_row + dy
            dy2 = (-0.5 * sy + (iy + 0.5) * wy - near_y) ** 2
            hit = (iy >= 0) & (iy < ny) & (dx2 + dy2 <= r2)
            covered[ix[hit], iy[hit]] = True
    return float(covered.mean())


def check_region(region) -> dict:
    """A target region, checked: ``{center_m: [x, y], radius_m: r}`` (a disc) or
    ``{min_m: [x, y], max_m: [x, y]}`` (an axis-aligned rectangle). Raises ValueError saying
    which key is wrong."""
    if not isinstance(region, dict):
        raise ValueError("must be a mapping {center_m, radius_m} or {min_m, max_m}")
    keys = set(region)
    if keys == {"center_m", "radius_m"}:
        _point(region["center_m"], "center_m")
        if not finite_number(region["radius_m"]) or region["radius_m"] <= 0:
            raise ValueError("radius_m must be a number > 0")
    elif keys == {"min_m", "max_m"}:
        lo, hi = _point(region["min_m"], "min_m"), _point(region["max_m"], "max_m")
        if not (lo[0] < hi[0] and lo[1] < hi[1]):
            raise ValueError("min_m must be below max_m on both axes")
    else:
        raise ValueError(f"has keys {sorted(keys)}: give center_m and radius_m, "
                         "or min_m and max_m")
    return region


def inside_region(region: dict, xy: np.ndarray) -> np.ndarray:
    """Whether each point of ``xy`` (T, 2) lies in the region (its boundary included)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if "center_m" in region:
        cx, cy = region["center_m"]
        return np.hypot(xy[:, 0] - cx, xy[:, 1] - cy) <= region["radius_m"]
    lo, hi = region["min_m"], region["max_m"]
    return (xy[:, 0] >= lo[0]) & (xy[:, 0] <= hi[0]) & (xy[:, 1] >= lo[1]) & (xy[:, 1] <= hi[1])


def finite_number(v) -> bool:
    """Whether ``v`` is a finite int or float (a bool is not a number here)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _point(v, key):
    if not (isinstance(v, (list, tuple)) and len(v) == 2 and all(finite_number(c) for c in v)):
        raise ValueError(f"{key} must be [x, y] in metres")
    return float(v[0]), float(v[1])

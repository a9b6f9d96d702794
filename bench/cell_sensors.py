#!/usr/bin/python3
"""The cell's sensors in the C++ core against numpy/pure-Python baselines, in the same run.

Builds a 6 m x 6 m cell (walls, tables, ~60 robot-link shapes), then times per call:
  - CollisionWorld.set_poses of 60 links against 60 set_pose calls;
  - a 682-beam LaserScanner.scan (Hokuyo, with noise) against numpy beams + one batched
    CollisionWorld.ray_cast + numpy noise and REP 117 limits;
  - RayProximityArray.read of 11 rays against numpy + CollisionWorld.ray_cast + frame changes;
  - DepthNoise.apply on 640x480 against numpy's Generator (ziggurat normals);
  - detect_blobs on a 128x128 mask with a few blobs against the tests' pure-Python reference
    of the same filter (test/core/vrep_blobs.py), and (if scipy is there) scipy.ndimage.label
    with numpy for the rest.
Prints the machine, then one JSON line per sensor with the median times and their ratio.
Needs a built workspace, sourced.
"""
import argparse
import json
import math
import os
import platform
import sys
import time

import numpy as np

from epuck_vrep_compat import (GROUP_FLOOR, GROUP_ROBOT, CollisionWorld, DepthNoise,
                               LaserScanner, RayProximityArray, detect_blobs)

# The tests' pure-Python reference of V-REP's blob filter is the blob baseline.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test", "core"))
from vrep_blobs import rectangle, vrep_blobs  # noqa: E402

IDENTITY = (0.0, 0.0, 0.0, 1.0)
LINKS = range(100, 160)


def cell():
    """Floor, four walls, two tables and 60 link shapes of robots standing in the cell."""
    world = CollisionWorld()
    world.add_box(1, (3, 3, 0.01), (0, 0, -0.01), IDENTITY, (0.8,) * 3, GROUP_FLOOR)
    for k, (hx, hy, x, y) in enumerate([(3, 0.05, 0, 3), (3, 0.05, 0, -3), (0.05, 3, 3, 0),
                                        (0.05, 3, -3, 0)]):
        world.add_box(2 + k, (hx, hy, 1), (x, y, 1), IDENTITY, (0.5,) * 3)
    world.add_box(10, (0.6, 0.4, 0.4), (1.5, 1.0, 0.4), IDENTITY, (0.6, 0.4, 0.2))
    world.add_box(11, (0.4, 0.8, 0.4), (-1.8, -0.5, 0.4), IDENTITY, (0.6, 0.4, 0.2))
    for handle, position in zip(LINKS, link_positions(0.0)):
        world.add_cylinder(handle, 0.06, 0.3, position, IDENTITY, (0.9, 0.5, 0.1), GROUP_ROBOT)
    return world


def link_positions(t):
    """60 links: 6 robots of 10 links, stacked and swaying with time t."""
    k = np.arange(60)
    robot, link = k // 10, k % 10
    angle = robot * math.pi / 3 + 0.3 * math.sin(t)
    return np.column_stack([1.8 * np.cos(angle) + 0.05 * link, 1.8 * np.sin(angle),
                            0.15 + 0.25 * link])


def median_ms(fn, repeats):
    fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times))


def rotations(quaternions):
    """Rotation matrices (M, 3, 3) of quaternions (M, 4) x, y, z, w."""
    x, y, z, w = np.asarray(quaternions, float).T
    rows = [(1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
            (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
            (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y))]
    return np.stack([np.stack(row, -1) for row in rows], -2)


def laser_baseline(world, scanner, position, yaw, rng):
    angles = scanner.angle_min_rad + yaw + scanner.angle_increment_rad * np.arange(scanner.count)
    directions = np.column_stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)])
    distance, _, _ = world.ray_cast(np.tile(position, (scanner.count, 1)), directions,
                                    scanner.range_max_m)
    sigma = np.maximum(scanner.sigma_min_m, scanner.sigma_rel * distance)
    noisy = np.clip(distance + sigma * rng.standard_normal(scanner.count), scanner.range_min_m,
                    scanner.range_max_m)
    ranges = np.where(np.isinf(distance), np.inf, noisy)
    return np.where(distance < scanner.range_min_m, -np.inf, ranges).astype(np.float32)


def proximity_baseline(world, positions, quaternions, min_m, max_m):
    rotation = rotations(quaternions)
    distance, handle, normal = world.ray_cast(positions, rotation[:, :, 2], max_m)
    detected = (distance >= min_m) & (distance <= max_m)
    points = np.where(detected[:, None], distance[:, None] * [0, 0, 1], 0.0)
    local_normals = np.einsum("mji,mj->mi", rotation, normal) * detected[:, None]
    return detected.astype(np.int32), distance, points, np.where(detected, handle, -1), \
        local_normals


def depth_baseline(depth, near, far, rng, a=0.0012, b=0.0019, c=0.4):
    sigma = a + b * (depth - c) ** 2
    noisy = np.clip(depth + sigma * rng.standard_normal(depth.shape, np.float32), near, far)
    return np.where(depth >= far, np.float32(far), noisy)


def blobs_scipy(mask, ndimage):
    """scipy's labelling, then numpy over each blob's pixels (their box is their boundary's)."""
    height, width = mask.shape
    labels, count = ndimage.label(mask[::-1], structure=np.ones((3, 3)))
    sizes = np.bincount(labels.ravel())[1:]
    rows = []
    for k in np.argsort(-sizes, kind="stable"):
        y, x = np.nonzero(labels == k + 1)
        rows.append((sizes[k] / mask.size,) + rectangle(np.column_stack([x, y]).astype(float),
                                                       width, height))
    return np.array(rows, np.float32)


def blob_mask():
    rows, cols = np.mgrid[:128, :128]
    mask = np.zeros((128, 128), bool)
    for row, col, radius in ((30, 40, 12), (90, 95, 9), (70, 30, 6), (20, 100, 4)):
        mask |= (rows - row) ** 2 + (cols - col) ** 2 <= radius ** 2
    mask[100:110, 20:60] = True
    return mask


def machine():
    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as info:
            model = next(line.split(":", 1)[1].strip() for line in info
                         if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"cpu": model, "cores": os.cpu_count(), "python": platform.python_version(),
            "numpy": np.__version__}


def report(sensor, ours_ms, baseline_ms, baseline):
    print(json.dumps({"sensor": sensor, "core_ms": round(ours_ms, 4),
                      baseline: round(baseline_ms, 4), "speedup": round(baseline_ms / ours_ms, 1)}))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=200)
    args = ap.parse_args()
    n = args.repeats
    print(json.dumps({"machine": machine()}))
    world = cell()
    rng = np.random.default_rng(1)

    quaternions = np.tile(IDENTITY, (60, 1))
    moved = link_positions(0.5)
    report("set_poses 60 links", median_ms(lambda: world.set_poses(LINKS, moved, quaternions), n),
           median_ms(lambda: [world.set_pose(h, p, IDENTITY) for h, p in zip(LINKS, moved)], n),
           "set_pose_loop_ms")

    scanner = LaserScanner(sigma_min_m=0.01, sigma_rel=0.01, seed=1)
    position, yaw = (0.2, -0.3, 0.3), 0.4
    q = (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
    ours = scanner.scan(world, position, q)
    base = laser_baseline(world, scanner, position, yaw, rng)
    assert np.array_equal(np.isinf(ours), np.isinf(base)) and np.isfinite(ours).sum() > 600
    report("laser 682 beams", median_ms(lambda: scanner.scan(world, position, q), n),
           median_ms(lambda: laser_baseline(world, scanner, position, yaw, rng), n),
           "numpy_ray_cast_ms")

    sensors = RayProximityArray(np.full(11, 0.02), np.full(11, 0.08))
    positions = link_positions(0.5)[3:14] + (0.0, -0.1, 0.0)
    turned = np.tile((-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)), (11, 1))  # +z -> world +y
    ours = sensors.read(world, positions, turned)
    base = proximity_baseline(world, positions, turned, 0.02, 0.08)
    assert np.array_equal(ours[0], base[0]) and np.allclose(ours[4], base[4])
    report("proximity 11 rays", median_ms(lambda: sensors.read(world, positions, turned), n),
           median_ms(lambda: proximity_baseline(world, positions, turned, 0.02, 0.08), n),
           "numpy_ray_cast_ms")

    depth = rng.uniform(0.5, 4.5, (480, 640)).astype(np.float32)
    depth[:40] = 5.0
    noise = DepthNoise(seed=1)
    report("depth noise 640x480", median_ms(lambda: noise.apply(depth, 0.5, 5.0), n // 4),
           median_ms(lambda: depth_baseline(depth, 0.5, 5.0, rng), n // 4), "numpy_ms")

    mask = blob_mask()
    ours = detect_blobs(mask)[2:].reshape(-1, 6)
    assert np.array_equal(ours, vrep_blobs(mask))
    report("blobs 128x128", median_ms(lambda: detect_blobs(mask), n),
           median_ms(lambda: vrep_blobs(mask), max(n // 20, 3)), "pure_python_ms")
    try:
        from scipy import ndimage
    except ImportError:
        return
    assert np.allclose(ours, blobs_scipy(mask, ndimage), atol=1e-6)
    report("blobs 128x128", median_ms(lambda: detect_blobs(mask), n),
           median_ms(lambda: blobs_scipy(mask, ndimage), n // 4), "scipy_numpy_ms")


if __name__ == "__main__":
    main()

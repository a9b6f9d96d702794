#!/usr/bin/python3
"""Camera render time against the one-ray-per-pixel baseline, measured in the same run.

Builds an arena with N e-pucks, renders from every 10th robot's camera with
``CollisionWorld.render`` and with a baseline that casts one ray per pixel through
``CollisionWorld.ray_cast`` (what a straightforward renderer does), and prints the times and
their ratio as one JSON line per image size. Needs a built workspace, sourced.
"""
import argparse
import json
import math
import time

import numpy as np

from epuck_vrep_compat import GROUP_FLOOR, GROUP_STATIC, CollisionWorld, EpuckModel, EpuckSwarm


def arena(n):
    side = 0.15 * math.ceil(math.sqrt(n)) + 0.1
    world = CollisionWorld()
    world.add_box(1, [side, side, 0.005], [0, 0, -0.005], [0, 0, 0, 1], [0.8] * 3, GROUP_FLOOR)
    for k, (hx, hy, x, y) in enumerate([(side / 2, 0.005, 0, side / 2),
                                        (side / 2, 0.005, 0, -side / 2),
                                        (0.005, side / 2, side / 2, 0),
                                        (0.005, side / 2, -side / 2, 0)]):
        world.add_box(2 + k, [hx, hy, 0.025], [x, y, 0.025], [0, 0, 0, 1], [0.5] * 3,
                      GROUP_STATIC)
    swarm = EpuckSwarm(world, EpuckModel(), 1)
    rng = np.random.default_rng(1)
    m = math.ceil(math.sqrt(n))
    cameras = []
    for i in range(n):
        x = -side / 2 + 0.1 + (i % m) * 0.15
        y = -side / 2 + 0.1 + (i // m) * 0.15
        yaw = rng.uniform(-math.pi, math.pi)
        swarm.add_robot(100 + i, x, y, yaw)
        q = [0, 0, math.sin(yaw / 2), math.cos(yaw / 2)]
        cameras.append((100 + i, [x + 0.037 * math.cos(yaw), y + 0.037 * math.sin(yaw), 0.028], q))
    return world, swarm, cameras


def baseline(world, handle, position, q, width, height, fov, near, far):
    f = 0.5 * height / math.tan(0.5 * fov)
    cols = (np.arange(width) + 0.5 - width / 2) / f
    rows = (np.arange(height) + 0.5 - height / 2) / f
    d = np.stack(np.broadcast_arrays(1.0, -cols[None, :], -rows[:, None]), -1).reshape(-1, 3)
    x, y, z, w = q
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    dirs = d @ r.T
    return world.ray_cast(np.tile(position, (len(dirs), 1)), dirs, far, handle)


def best_ms(fn, cameras, repeats=5):
    times = []
    for camera in cameras:
        for _ in range(repeats):
            start = time.perf_counter()
            fn(*camera)
            times.append(time.perf_counter() - start)
    return 1e3 * float(np.mean(np.sort(times)[:len(cameras)]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robots", type=int, nargs="+", default=[100, 1000])
    args = ap.parse_args()
    for n in args.robots:
        world, _swarm, cameras = arena(n)
        sample = cameras[::10]
        for width, height in ((160, 120), (40, 40)):
            ours = best_ms(lambda h, p, q: world.render(p, q, width, height, 0.84, 0.005, 2.0, h),
                           sample)
            base = best_ms(lambda h, p, q: baseline(world, h, p, q, width, height, 0.84, 0.005,
                                                    2.0), sample, repeats=2)
            print(json.dumps({"robots": n, "image": f"{width}x{height}", "render_ms": round(ours, 3),
                              "one_ray_per_pixel_ms": round(base, 3),
                              "speedup": round(base / ours, 1)}))


if __name__ == "__main__":
    main()

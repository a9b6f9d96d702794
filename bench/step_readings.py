#!/usr/bin/python3
"""Every reading of the e-pucks' step over a fixed set of runs, saved to compare two builds of
the core bit for bit.

Making the step faster must change no reading. Record with the tree before a change, rebuild,
record again and compare: every array must be equal bit for bit (``0 differ``). The arrays
depend on the machine (compiler, libm), so they are never committed; the comparison is between
two builds on one machine.

    /usr/bin/python3 bench/step_readings.py --out /tmp/before.npz
    (change the core, rebuild)
    /usr/bin/python3 bench/step_readings.py --out /tmp/after.npz --compare /tmp/before.npz

The runs, each for --steps steps with seeded commands:
- ``bench``: the learning benchmark's worlds (bench/learn_bench.py), B x R = 1 x 1000, 100 x 10
  and 1000 x 1, noise off (as benchmarked) and 20 x 10, 1 x 300 with the real robot's noise;
- ``crowd``: robots packed shoulder to shoulder in small walled arenas (walls turned by a yaw,
  boxes and cylinders among them), driving into each other and the walls, noise on;
- ``task``: the learning tasks' worlds (learn/worlds.py, noise ``real_robot`` and ``ideal``),
  their arenas drawn anew for some worlds every 40 steps (obstacles cleared and added, worlds
  reset);
- ``sim``: the ROS simulation's swarm, ``build_simulation`` of worlds/arena.yaml with 12
  e-pucks, the paper's noise and the e-puck2's sensors, an obstacle moved and a reset midway.
Each step saves poses, velocities, wheel speeds and angles, odometry, noisy and clean ranges,
accelerometer, gyroscope, contacts, and every sensor's detected handle, point and normal
(every 10th step for the largest runs' detections).
"""
import argparse
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import learn_bench  # noqa: E402 (beside this script: the benchmark's worlds)

from epuck_vrep_compat import _core  # noqa: E402
from epuck_vrep_compat.epuck.noise_presets import preset  # noqa: E402

CORE_OUTPUTS = ("poses", "velocities", "wheel_speeds", "odometry", "ranges", "ranges_clean",
                "accel", "gyro", "in_contact")
SWARM_OUTPUTS = ("wheel_angles", "detected_handles", "detected_points", "detected_normals")


class Recorder:
    """Arrays per key, one row a step, stacked at the end."""

    def __init__(self):
        self.rows = {}

    def add(self, key, value):
        self.rows.setdefault(key, []).append(np.array(value, copy=True))

    def arrays(self):
        return {key: np.stack(rows) for key, rows in self.rows.items()}


def record_batched(rec, name, core, step, detect_every=1):
    """Everything of one BatchedWorlds step under ``name/``."""
    for key in CORE_OUTPUTS:
        rec.add(f"{name}/{key}", getattr(core, key))
    rec.add(f"{name}/frames", core.frames)
    if step % detect_every == 0:
        for key in SWARM_OUTPUTS:
            rec.add(f"{name}/{key}",
                    np.concatenate([getattr(core.swarm(b), key) for b in range(core.worlds)]))


def noisy(core):
    preset("real_robot").apply(core, [f"r{i}" for i in range(core.size)])


def run_bench(rec, steps):
    runs = [(1, 1000, False), (100, 10, False), (1000, 1, False), (20, 10, True),
            (1, 300, True)]
    for worlds, robots, noise in runs:
        name = f"bench_{worlds}x{robots}_{'noise' if noise else 'clean'}"
        core = learn_bench.build_ours(worlds, robots, seed=7)
        if noise:
            noisy(core)
        commands = learn_bench.command_table(worlds, robots, seed=7)
        every = 10 if worlds * robots >= 1000 else 1
        for i in range(steps):
            core.step(learn_bench.STEP_S, commands[i % len(commands)])
            record_batched(rec, name, core, i, every)


def build_crowd(worlds, robots, side_m, seed):
    """Robots on a grid of 7.5 cm cells (touching) in a square of ``side_m`` walled by four
    boxes turned by a small yaw, with a box and a cylinder among them."""
    core = _core.BatchedWorlds(_core.EpuckModel(), worlds, robots,
                               [seed + b for b in range(worlds)])
    rng = np.random.default_rng(seed)
    half, t = side_m / 2, 0.02
    per_row = math.ceil(math.sqrt(robots))
    for b in range(worlds):
        yaw = float(rng.uniform(-0.05, 0.05))
        c, s = math.cos(yaw), math.sin(yaw)
        for cx, cy, hx, hy in ((0, half + t, half + t, t), (0, -half - t, half + t, t),
                               (half + t, 0, t, half + t), (-half - t, 0, t, half + t)):
            core.add_box(b, (c * cx - s * cy, s * cx + c * cy, 0.025), (hx, hy, 0.025), yaw)
        core.add_box(b, (0.6 * half, -0.6 * half, 0.03), (0.04, 0.02, 0.03), 0.7)
        core.add_cylinder(b, (-0.6 * half, 0.6 * half, 0.04), 0.03, 0.08)
        for r in range(robots):
            x = -half + 0.05 + 0.075 * (r % per_row) + float(rng.uniform(-0.01, 0.01))
            y = -half + 0.05 + 0.075 * (r // per_row) + float(rng.uniform(-0.01, 0.01))
            core.set_pose(b, r, x, y, float(rng.uniform(-math.pi, math.pi)))
    noisy(core)
    return core


def run_crowd(rec, steps):
    for worlds, robots, side_m in ((1, 60, 0.7), (10, 8, 0.3)):
        core = build_crowd(worlds, robots, side_m, seed=11)
        rng = np.random.default_rng(11)
        for i in range(steps):
            core.step(0.05, rng.uniform(-6.28, 6.28, (core.size, 2)))
            record_batched(rec, f"crowd_{worlds}x{robots}", core, i)


def run_tasks(rec, steps):
    from epuck_vrep_compat.learn.tasks import make_task
    from epuck_vrep_compat.learn.worlds import Worlds
    for task_name, robots in (("obstacle_avoidance", 1), ("obstacle_avoidance", 3),
                              ("aggregation", 5), ("follow_leader", 2)):
        for noise in ("real_robot", "ideal"):
            name = f"task_{task_name}_{robots}_{noise}"
            worlds = Worlds(make_task(task_name, robots=robots), 8, noise=noise,
                            multi_agent=True)
            for b in range(worlds.count):
                worlds.seed(b, 100 + b)
                worlds.place(b)
            rng = np.random.default_rng(5)
            for i in range(steps):
                if i % 40 == 39:
                    for b in range(0, worlds.count, 3):
                        worlds.place(b)
                actions = rng.uniform(-1, 1, (worlds.count, len(worlds.agents), 2))
                rec.add(f"{name}/rewards", worlds.step(actions))
                rec.add(f"{name}/obs", worlds.obs)
                record_batched(rec, name, worlds.core, i)


def run_sim(rec, steps):
    from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
    from epuck_vrep_compat.epuck.epuck2_sensors import Epuck2Settings
    from epuck_vrep_compat.scene.scene_file import load_scene
    repo = os.path.dirname(HERE)
    scene = load_scene(os.path.join(repo, "worlds", "arena.yaml"))
    names = [f"ePuck{k}" for k in range(12)]
    sim = build_simulation(scene, SimulationConfig(names, seed=3, epuck2=Epuck2Settings()))
    rng = np.random.default_rng(3)
    swarm = sim.epucks.swarm
    _obstacle, handle = sim.obstacles[0]
    obstacle = sim.registry.get(handle)
    for i in range(steps):
        if i == steps // 3:
            sim.move_object(obstacle, (0.1, 0.3, 0.025), (0.0, 0.0, 0.0, 1.0))
        if i == 2 * steps // 3:
            sim.reset()
        for name in names:
            left, right = rng.uniform(-6.28, 6.28, 2)
            sim.epucks.set_wheel_speeds(name, float(left), float(right))
        sim.step()
        for key in CORE_OUTPUTS + SWARM_OUTPUTS:
            rec.add(f"sim/{key}", getattr(swarm, key))
        rec.add("sim/tof_m", sim.epuck2.tof_m)


def compare(now, path):
    """Prints each array that differs from the recording at ``path``; returns how many."""
    before = dict(np.load(path))
    differ = 0
    for key in sorted(set(before) | set(now)):
        if key not in before or key not in now:
            print(f"{key}: only in {'the recording' if key in before else 'this run'}")
            differ += 1
            continue
        a, b = before[key], now[key]
        if a.shape != b.shape or a.dtype != b.dtype:
            print(f"{key}: shape or type {a.shape} {a.dtype} -> {b.shape} {b.dtype}")
            differ += 1
            continue
        if a.dtype.kind == "f":   # bit for bit: -0.0 differs from 0.0, NaN equals NaN
            same = ((a == b) & (np.signbit(a) == np.signbit(b))) | (np.isnan(a) & np.isnan(b))
        else:
            same = a == b
        if not same.all():
            diff = np.abs(a.astype(float) - b.astype(float))[~same]
            print(f"{key}: {int((~same).sum())} of {a.size} values differ, "
                  f"largest by {np.nanmax(diff):.3g}")
            differ += 1
    print(f"{len(set(before) | set(now))} arrays, {differ} differ")
    return differ


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help=".npz to write the readings to")
    parser.add_argument("--compare", help="an earlier recording to compare with")
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--only", nargs="*", default=["bench", "crowd", "task", "sim"])
    args = parser.parse_args()
    rec = Recorder()
    runs = {"bench": run_bench, "crowd": run_crowd, "task": run_tasks, "sim": run_sim}
    for name in args.only:
        runs[name](rec, args.steps)
    arrays = rec.arrays()
    np.savez_compressed(args.out, **arrays)
    print(f"{len(arrays)} arrays written to {args.out}")
    if args.compare:
        sys.exit(1 if compare(arrays, args.compare) else 0)


if __name__ == "__main__":
    main()

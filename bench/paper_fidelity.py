#!/usr/bin/python3
"""The e-puck paper's Table 1 and its proximity noise, measured on our simulator: the README's
fidelity table. Statistics of simulated time, not timing: any machine gives the same numbers
for the same seed.

One e-puck with the default parameters (no noise settings given: the paper's real robot) in
the paper's scenarios (worlds/paper_straight.yaml, worlds/paper_rest.yaml):
- driving straight at 4 cm/s for 20 s of simulated time (400 readings, the issue's
  measurement), the accelerometer's per-axis mean and SD and sensor 0's wrong readings;
- the same over 200 s (4 000 readings) and sensor 0 at rest over 12 000 readings, where the
  sampling error is small enough to compare with the paper's figures to their precision.
Prints a Markdown table (``--json`` also writes the numbers). Needs a built workspace, sourced.
"""
import argparse
import json
import os

import numpy as np

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.epuck import paper_robot as paper
from epuck_vrep_compat.scene.scene_file import load_scene

WORLDS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "worlds")
WHEEL_RADIUS_M = 0.02


def run(world, speed_m_s, readings, seed):
    """(accel (N, 3), proximity0 (N,)) of ``readings`` steps, after 0.5 s of getting under way."""
    sim = build_simulation(load_scene(os.path.join(WORLDS, world)),
                           SimulationConfig(["ePuck0"], seed=seed))
    accel, prox = [], []
    for i in range(readings + 10):
        wheel_rad_s = speed_m_s / WHEEL_RADIUS_M
        sim.epucks.set_wheel_speeds("ePuck0", wheel_rad_s, wheel_rad_s)
        sim.step()
        if i >= 10:
            accel.append(sim.epucks.swarm.accel[0].copy())
            prox.append(sim.epucks.swarm.ranges[0, 0])
    return np.array(accel), np.array(prox)


def measure(seed):
    short_accel, short_prox = run("paper_straight.yaml", paper.PAPER_SPEED_M_S, 400, seed)
    long_accel, _ = run("paper_straight.yaml", paper.PAPER_SPEED_M_S, 4000, seed)
    _, rest_prox = run("paper_rest.yaml", 0.0, 12000, seed)
    return {
        "accel_mean_400": short_accel.mean(axis=0).tolist(),
        "accel_sd_400": short_accel.std(axis=0, ddof=1).tolist(),
        "accel_mean_4000": long_accel.mean(axis=0).tolist(),
        "accel_sd_4000": long_accel.std(axis=0, ddof=1).tolist(),
        "prox0_wrong_400": [int((short_prox < 0.05).sum()), int(short_prox.size)],
        "prox0_wrong_rest_12000": [int((rest_prox < 0.05).sum()), int(rest_prox.size)],
    }


def table(m):
    rows = ["| | real robot (Table 1) | ours, 20 s (400 readings) | ours, 200 s (4 000) |",
            "| --- | --- | --- | --- |"]
    for axis, name in enumerate("xyz"):
        rows.append(f"| accel {name} mean / sd [m/s²] | "
                    f"{paper.TABLE1_REAL_MEAN_M_S2[axis]:.4f} / "
                    f"{paper.TABLE1_REAL_STDDEV_M_S2[axis]:.4f} | "
                    f"{m['accel_mean_400'][axis]:.4f} / {m['accel_sd_400'][axis]:.4f} | "
                    f"{m['accel_mean_4000'][axis]:.4f} / {m['accel_sd_4000'][axis]:.4f} |")
    k, n = m["prox0_wrong_400"]
    kr, nr = m["prox0_wrong_rest_12000"]
    rows.append(f"| proximity0 readings that are not max range, in open space | 61/380 = 0.161 "
                f"| {k}/{n} = {k / n:.3f} (driving) | {kr}/{nr} = {kr / nr:.3f} (at rest) |")
    return "\n".join(rows)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", default=None, help="also write the numbers to this file")
    args = parser.parse_args()
    m = measure(args.seed)
    print(table(m))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(dict(m, seed=args.seed), f, indent=1)


if __name__ == "__main__":
    main()

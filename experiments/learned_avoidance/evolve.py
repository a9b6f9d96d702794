#!/usr/bin/python3
"""Evolve the obstacle avoider with CMA-ES on the batched worlds, then test it.

    python3 experiments/learned_avoidance/evolve.py --out results/evolve     # a few minutes

Each generation scores every candidate perceptron (the policy package's, 18 weights on the 8
IR activations) by Floreano and Mondada's fitness averaged over ``--arenas`` seeded arenas of
``EpuckObstacleAvoidance-v0`` (the same arenas for every candidate of a generation, new ones
each generation), all candidates' worlds stepped together in one vector environment. Writes
to ``--out``: ``evolved.json`` (the best mean's weights, for ``policy_node _weights:=``),
``curve.csv`` and ``curve.png`` (best and mean fitness per generation), and ``test.csv``: the
evolved controller and the hand-set Braitenberg avoider on ``--test-seeds`` arenas never
used in training (fitness, steps in contact, contact onsets).
"""
import argparse
import csv
import os
import time

import cma
import gymnasium as gym
import numpy as np

import epuck_vrep_compat.learn  # noqa: F401 (registers the environments)
from epuck_vrep_compat.policy.controller import Perceptron, braitenberg
from epuck_vrep_compat.policy.observation import ObservationLayout

ENV = "EpuckObstacleAvoidance-v0"
TEST_SEED_BASE = 1_000_000           # test arenas: seeds no generation draws


def run_episodes(envs, controllers, world_seeds, steps):
    """Per controller (each on len(world_seeds) / len(controllers) consecutive worlds): mean
    fitness, steps in contact and contact onsets per world."""
    obs, _ = envs.reset(options={"world_seeds": world_seeds})
    per = len(world_seeds) // len(controllers)
    fitness = np.zeros(len(world_seeds))
    touching = np.zeros(len(world_seeds))
    onsets = np.zeros(len(world_seeds))
    before = np.zeros(len(world_seeds), dtype=bool)
    for _ in range(steps):
        action = np.concatenate([c(obs[k * per:(k + 1) * per])
                                 for k, c in enumerate(controllers)])
        obs, reward, _, _, info = envs.step(action)
        contact = info["in_contact"]
        fitness += reward
        touching += contact
        onsets += contact & ~before
        before = contact
    shape = (len(controllers), per)
    return ((fitness / steps).reshape(shape).mean(axis=1), touching.reshape(shape),
            onsets.reshape(shape))


def evolve(args):
    layout = ObservationLayout()
    n = Perceptron.parameter_count(layout)
    es = cma.CMAEvolutionStrategy(np.zeros(n), args.sigma,
                                  {"seed": args.seed, "popsize": args.popsize, "verbose": -9})
    envs = gym.make_vec(ENV, num_envs=args.popsize * args.arenas, noise=args.noise,
                        episode_steps=args.steps + 1)
    rows, started = [], time.monotonic()
    for generation in range(args.generations):
        candidates = es.ask()
        seeds = [args.seed * 100_000 + generation * args.arenas + k
                 for _ in candidates for k in range(args.arenas)]
        controllers = [Perceptron.from_flat(x, layout) for x in candidates]
        fitness, _, _ = run_episodes(envs, controllers, seeds, args.steps)
        es.tell(candidates, (-fitness).tolist())
        rows.append((generation, float(fitness.max()), float(fitness.mean()),
                     time.monotonic() - started))
        print(f"generation {generation:3d}: best {fitness.max():.3f} mean {fitness.mean():.3f} "
              f"({rows[-1][3]:.0f} s)", flush=True)
    envs.close()
    meta = {"task": ENV, "fitness": "Floreano & Mondada 1994, mean per step",
            "generations": args.generations, "popsize": args.popsize, "arenas": args.arenas,
            "steps": args.steps, "noise": args.noise, "seed": args.seed,
            "wall_time_s": round(rows[-1][3], 1)}
    return Perceptron.from_flat(es.result.xfavorite, layout, meta), rows


def test(args, evolved):
    """Both controllers on the same held-out arenas: rows per controller and arena."""
    seeds = [TEST_SEED_BASE + k for k in range(args.test_seeds)]
    envs = gym.make_vec(ENV, num_envs=2 * args.test_seeds, noise=args.noise,
                        episode_steps=args.test_steps + 1)
    named = {"evolved": evolved, "braitenberg": braitenberg()}
    fitness, touching, onsets = run_episodes(envs, [c for c in named.values() for _ in seeds],
                                             seeds * 2, args.test_steps)
    envs.close()
    rows = []
    for k, name in enumerate(named):
        for j, seed in enumerate(seeds):
            w = k * len(seeds) + j
            rows.append((name, seed, float(fitness[w]), int(touching[w, 0]),
                         int(onsets[w, 0])))
    return rows


def write(args, evolved, curve, tested):
    os.makedirs(args.out, exist_ok=True)
    evolved.save(os.path.join(args.out, "evolved.json"))
    with open(os.path.join(args.out, "curve.csv"), "w", newline="") as f:
        csv.writer(f).writerows([("generation", "best", "mean", "wall_s")] + curve)
    with open(os.path.join(args.out, "test.csv"), "w", newline="") as f:
        csv.writer(f).writerows([("controller", "seed", "fitness", "contact_steps",
                                  "contact_onsets")] + tested)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    g = [r[0] for r in curve]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(g, [r[1] for r in curve], label="best candidate")
    ax.plot(g, [r[2] for r in curve], label="population mean")
    ax.set_xlabel("generation")
    ax.set_ylabel("fitness (Floreano & Mondada)")
    ax.set_title(f"CMA-ES, {args.popsize} candidates x {args.arenas} arenas x {args.steps} steps")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "curve.png"), dpi=120)
    for name in ("evolved", "braitenberg"):
        mine = [r for r in tested if r[0] == name]
        print(f"{name}: fitness {np.mean([r[2] for r in mine]):.3f}, arenas without contact "
              f"{sum(r[3] == 0 for r in mine)}/{len(mine)}, contact onsets "
              f"{sum(r[4] for r in mine)}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="results/evolve")
    parser.add_argument("--generations", type=int, default=60)
    parser.add_argument("--popsize", type=int, default=16)
    parser.add_argument("--arenas", type=int, default=8, help="arenas per candidate")
    parser.add_argument("--steps", type=int, default=600, help="steps of 50 ms per episode")
    parser.add_argument("--sigma", type=float, default=0.5)
    parser.add_argument("--noise", default="real_robot")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--test-seeds", type=int, default=20)
    parser.add_argument("--test-steps", type=int, default=600)
    args = parser.parse_args(argv)
    evolved, curve = evolve(args)
    write(args, evolved, curve, test(args, evolved))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

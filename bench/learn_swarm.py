"""The learning benchmark's swarm row (bench/learn_bench.py, ``--peers swarm``): the batched
PettingZoo environment (``EpuckParallelVectorEnv``) at B worlds x R robots, every robot an agent.

Its worlds are the obstacle-avoidance task's (a 1 m walled square, 6 cylinders drawn anew at each
reset, 20 s episodes reset per world as training does), not the grid arena of the other peers,
so it is shown in a table of its own: what a multi-agent learner gets per second through each
form of the interface, with the observations, rewards and autoresets included. R is at most
MAX_ROBOTS (the 1 m square holds no more with room at the start). Timed, each in turn on the same
environment, actions from a seeded table of 50 sets uniform in [-1, 1]:
(c) ``step_arrays`` (B, A, 2) in, arrays out; (d) ``step`` with a dict of (B, 2) arrays in, dicts
out; (e) the flat Gymnasium view's ``step`` (B x A, 2).
"""
import time

import numpy as np

MAX_ROBOTS = 10
COMMAND_SETS = 50
WARMUP_STEPS = 5


def run_swarm(worlds, robots, steps, seed, rss_mb):
    """One JSON record of the three forms' robot-steps per second; ``rss_mb()`` the process's
    resident memory in MB, for the memory per world."""
    from epuck_vrep_compat.learn.flat_vector import EpuckFlatVectorEnv
    from epuck_vrep_compat.learn.parallel_vector import EpuckParallelVectorEnv
    commands = np.random.default_rng(seed).uniform(-1, 1, (COMMAND_SETS, worlds, robots, 2))
    before = rss_mb()
    env = EpuckParallelVectorEnv(worlds, "obstacle_avoidance", robots=robots)
    env.reset(seed=seed)
    growth = rss_mb() - before
    flat = EpuckFlatVectorEnv(env)
    agents = env.possible_agents
    forms = {"c_arrays": env.step_arrays,
             "d_dicts": lambda c: env.step({a: c[:, k] for k, a in enumerate(agents)}),
             "e_flat": lambda c: flat.step(c.reshape(-1, 2))}
    record = {"peer": "swarm", "worlds": worlds, "robots": robots, "steps": steps,
              "memory_per_world_kb": 1e3 * growth / worlds}
    for name, step in forms.items():
        for i in range(WARMUP_STEPS):
            step(commands[i % COMMAND_SETS])
        start = time.perf_counter()
        for i in range(steps):
            step(commands[i % COMMAND_SETS])
        record[f"{name}_robot_steps_per_s"] = worlds * robots * steps / (
            time.perf_counter() - start)
    return record


def swarm_table(records, rate):
    """The swarm records as a markdown table (``rate`` formats robot-steps per second)."""
    rows = [r for r in records if r["peer"] == "swarm"]
    if not rows:
        return ""
    lines = ["| B × A (swarm env, obstacle avoidance) | (c) step_arrays | (d) step, dicts | "
             "(e) flat view step | kB per world |", "| --- " * 5 + "|"]
    for r in sorted(rows, key=lambda r: -r["robots"]):
        lines.append(f"| {r['worlds']} × {r['robots']} | {rate(r['c_arrays_robot_steps_per_s'])}"
                     f" | {rate(r['d_dicts_robot_steps_per_s'])} | "
                     f"{rate(r['e_flat_robot_steps_per_s'])} | {r['memory_per_world_kb']:.0f} |")
    return "\n".join(lines)

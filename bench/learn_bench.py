#!/usr/bin/python3
"""Batched learning worlds: robot-steps per second on one core, ours against Enki.

The task (issue 25): B worlds of R e-pucks each, B x R = 1 x 1000, 100 x 10 and 1000 x 1, a
50 ms step, IR observations. Each world is the swarm benchmark's arena (bench/enki_peer.py and
bench/enki_swarm.cpp: a walled square, one robot per 30 cm cell of a grid, headings from a
seeded generator) with max(2, R // 10) static cylinders (r 2 cm, 8 cm tall) placed as
enki_swarm.cpp places them. Wheel commands are random-ish: a seeded table of 50 command sets,
uniform in [-2, 6] rad/s per wheel, replayed in turn.

What is timed, each configuration in a fresh process pinned to one CPU (--cpu):
- ours (a): ``BatchedWorlds.step`` alone, the C++ call (every world, contacts, IR cones, IMU);
- ours (b): the Python loop a learning environment runs: step, then read the observation
  arrays (``ranges``, ``poses``, ``in_contact``: copies); (b) - (a) is what the Python
  interface adds, shown per step;
- pyenki (Debian's python3-enki2), as its users step worlds: a Python loop of ``world.step``
  over the B worlds (a'), then every robot's ``proximitySensorValues`` read and its wheel
  speeds set from Python (b'). pyenki's e-puck always renders its linear camera too
  (bench/enki_peer.py says why); nothing in Python can switch that off;
- Enki C++ (bench/build/enki_swarm --worlds B --cylinders C, built by bench/build.sh if
  missing): Enki's library from C++ at the same 50 ms step, its Braitenberg controller in C++
  reading the IR sensors.
Memory per world: resident memory added by building the B worlds and stepping them once,
divided by B. In a table of its own, the swarm's batched PettingZoo environment through each
form of its interface (``--peers swarm``, bench/learn_swarm.py: the learning task's arena, so
not the same worlds; R <= 10).

Run on an idle machine: ``/usr/bin/python3 bench/learn_bench.py`` (a few minutes; add
``--json`` for the records). ``--robot-steps`` and ``--peer-robot-steps`` set how much is timed.
"""
import argparse
import json
import math
import os
import platform
import random
import subprocess
import sys
import time

# One core means one thread: OpenBLAS's idle workers would otherwise spin on the pinned CPU
# (seen in perf as sched_yield, 15 % of the samples). Set before numpy loads it.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import numpy as np  # noqa: E402

import learn_swarm  # noqa: E402 (beside this script)

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIGS = ((1, 1000), (100, 10), (1000, 1))
STEP_S = 0.05
CELL_M = 0.30            # as enki_peer.py and enki_swarm.cpp
ARENA_MARGIN_M = 0.10
WALL_M = (0.01, 0.10)    # thickness, height
CYLINDER_M = (0.02, 0.08, 0.10)   # radius, height, offset from the cell centre (enki_swarm.cpp)
COMMAND_SETS = 50
COMMAND_RAD_S = (-2.0, 6.0)
WHEEL_RADIUS_M = 0.0205
WARMUP_STEPS = 5


def grid(robots):
    """(per_row, arena side m, [(x, y) of each robot's cell centre])."""
    per_row = math.ceil(math.sqrt(robots))
    centres = [(ARENA_MARGIN_M / 2 + (i % per_row + 0.5) * CELL_M,
                ARENA_MARGIN_M / 2 + (i // per_row + 0.5) * CELL_M) for i in range(robots)]
    return per_row, CELL_M * per_row + ARENA_MARGIN_M, centres


def cylinder_count(robots):
    return max(2, robots // 10)


def cylinders(robots):
    """Centres (x, y) of one world's cylinders, as enki_swarm.cpp places them."""
    _per_row, _side, centres = grid(robots)
    offset = CYLINDER_M[2]
    found = []
    for k in range(cylinder_count(robots)):
        x, y = centres[(7 * k) % robots]
        sign = 1.0 if k % 2 == 0 else -1.0
        found.append((x + sign * offset, y + sign * offset))
    return found


def command_table(worlds, robots, seed):
    low, high = COMMAND_RAD_S
    return np.random.default_rng(seed).uniform(low, high, (COMMAND_SETS, worlds * robots, 2))


def rss_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e6


def build_ours(worlds, robots, seed):
    from epuck_vrep_compat import _core
    batched = _core.BatchedWorlds(_core.EpuckModel(), worlds, robots,
                                  [seed + b for b in range(worlds)])
    _per_row, side, centres = grid(robots)
    t, h = WALL_M
    walls = (((side / 2, -t / 2, h / 2), (side / 2 + t, t / 2, h / 2)),
             ((side / 2, side + t / 2, h / 2), (side / 2 + t, t / 2, h / 2)),
             ((-t / 2, side / 2, h / 2), (t / 2, side / 2, h / 2)),
             ((side + t / 2, side / 2, h / 2), (t / 2, side / 2, h / 2)))
    radius, height, _offset = CYLINDER_M
    for b in range(worlds):
        for centre, half in walls:
            batched.add_box(b, centre, half)
        for x, y in cylinders(robots):
            batched.add_cylinder(b, (x, y, height / 2), radius, height)
        headings = random.Random(seed + b)
        for r, (x, y) in enumerate(centres):
            batched.set_pose(b, r, x, y, headings.uniform(-math.pi, math.pi))
    return batched


def run_ours(worlds, robots, steps, seed):
    """(a) the step calls and (b) the loop reading the observations, one JSON record."""
    from epuck_vrep_compat import _core  # noqa: F401 (loaded before memory is counted)
    commands = command_table(worlds, robots, seed)
    before = rss_mb()
    batched = build_ours(worlds, robots, seed)
    batched.step(STEP_S, commands[0])
    growth = rss_mb() - before
    for i in range(WARMUP_STEPS):
        batched.step(STEP_S, commands[i % COMMAND_SETS])
    in_step = 0.0
    start = time.perf_counter()
    for i in range(steps):
        t0 = time.perf_counter()
        batched.step(STEP_S, commands[i % COMMAND_SETS])
        in_step += time.perf_counter() - t0
        _observations = (batched.ranges, batched.poses, batched.in_contact)
    loop = time.perf_counter() - start
    n = worlds * robots
    return {"peer": "ours", "worlds": worlds, "robots": robots, "steps": steps,
            "a_robot_steps_per_s": n * steps / in_step, "b_robot_steps_per_s": n * steps / loop,
            "python_overhead_us_per_step": 1e6 * (loop - in_step) / steps,
            "memory_per_world_kb": 1e3 * growth / worlds}


def run_pyenki(worlds, robots, steps, seed):
    """pyenki as its users step it: world.step over the worlds (a'), then the IR read and the
    wheel speeds set per robot from Python (b'), one JSON record."""
    import enki_peer  # imports pyenki
    import pyenki
    commands = command_table(worlds, robots, seed) * (WHEEL_RADIUS_M * enki_peer.CM_PER_M)
    before = rss_mb()
    built = []
    radius, height, _offset = CYLINDER_M
    cm = enki_peer.CM_PER_M
    for b in range(worlds):
        world, robots_of_world = enki_peer.build_world(robots, "none", seed + b, CELL_M)
        obstacles = []
        for x, y in cylinders(robots):
            cylinder = pyenki.CircularObject(radius * cm, height * cm, -1.0)
            cylinder.pos = (x * cm, y * cm)
            world.addObject(cylinder)
            obstacles.append(cylinder)   # pyenki's World does not own what it holds
        built.append((world, robots_of_world, obstacles))
    every_robot = [robot for _world, group, _obstacles in built for robot in group]
    for world, _group, _obstacles in built:
        world.step(STEP_S)
    growth = rss_mb() - before
    in_step = 0.0
    start = time.perf_counter()
    for i in range(WARMUP_STEPS + steps):
        if i == WARMUP_STEPS:
            in_step, start = 0.0, time.perf_counter()
        t0 = time.perf_counter()
        for world, _group, _obstacles in built:
            world.step(STEP_S)
        in_step += time.perf_counter() - t0
        command = commands[i % COMMAND_SETS]
        for robot, (left, right) in zip(every_robot, command.tolist()):
            _ir = robot.proximitySensorValues
            robot.leftSpeed, robot.rightSpeed = left, right
    loop = time.perf_counter() - start
    n = worlds * robots
    return {"peer": "pyenki", "worlds": worlds, "robots": robots, "steps": steps,
            "a_robot_steps_per_s": n * steps / in_step, "b_robot_steps_per_s": n * steps / loop,
            "memory_per_world_kb": 1e3 * growth / worlds}


def run_enki_cpp(worlds, robots, steps, seed):
    """Enki's library from C++ (bench/build/enki_swarm), one JSON record."""
    binary = os.path.join(HERE, "build", "enki_swarm")
    if not os.path.exists(binary):
        subprocess.run(["sh", os.path.join(HERE, "build.sh")], check=True,
                       stdout=subprocess.DEVNULL)
    out = subprocess.run([binary, "--robots", str(robots), "--worlds", str(worlds),
                          "--cylinders", str(cylinder_count(robots)), "--step", str(STEP_S),
                          "--sim-seconds", str(steps * STEP_S),
                          "--warmup-seconds", str(WARMUP_STEPS * STEP_S),
                          "--cell-m", str(CELL_M), "--seed", str(seed)],
                         check=True, stdout=subprocess.PIPE, text=True).stdout
    record = json.loads(out)
    n = worlds * robots
    return {"peer": "enki_cpp", "worlds": worlds, "robots": robots, "steps": steps,
            "a_robot_steps_per_s": record["rtf"] / STEP_S * n,
            "memory_per_world_kb": 1e3 * record["rss_growth_mb"] / worlds}


def run_swarm(worlds, robots, steps, seed):
    return learn_swarm.run_swarm(worlds, robots, steps, seed, rss_mb)


WORKERS = {"ours": run_ours, "pyenki": run_pyenki, "enki_cpp": run_enki_cpp, "swarm": run_swarm}


def in_child(peer, worlds, robots, steps, seed):
    command = [sys.executable, os.path.abspath(__file__), "--worker", peer, "--worlds",
               str(worlds), "--robots", str(robots), "--steps", str(steps), "--seed", str(seed)]
    out = subprocess.run(command, check=True, stdout=subprocess.PIPE, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def machine():
    """One line about the machine and what else ran on it."""
    model = "unknown CPU"
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    with open("/proc/meminfo") as f:
        mem_gb = int(f.readline().split()[1]) / 1024 ** 2
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    enki = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", "python3-enki2"],
                          stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout
    return (f"{model}, {os.cpu_count()} CPUs, {mem_gb:.1f} GB, Linux {platform.release()}, "
            f"Python {platform.python_version()}, numpy {np.__version__}, python3-enki2 "
            f"{enki or '?'}; pinned to CPU {sorted(os.sched_getaffinity(0))}; load average at "
            f"start {load}")


def _rate(value):
    if value is None:
        return "—"
    return f"{value / 1e6:.2f} M" if value >= 1e5 else f"{value / 1e3:.1f} k"


def _ratio(ours, peer):
    return "—" if not ours or not peer else f"{ours / peer:.1f}×"


def markdown_table(records):
    """One row per configuration: robot-steps per second and memory per world."""
    lines = ["| B × R | ours (a) step call | ours (b) loop + observations | Python µs/step "
             "(b − a) | pyenki (a′) world.step / (b′) + IR read | Enki C++ 50 ms | "
             "(a) ÷ Enki C++ | (b) ÷ pyenki (b′) | kB per world: ours / pyenki / Enki C++ |",
             "| --- " * 9 + "|"]
    for worlds, robots in sorted({(r["worlds"], r["robots"]) for r in records},
                                 key=lambda c: -c[1]):
        row = {r["peer"]: r for r in records if (r["worlds"], r["robots"]) == (worlds, robots)}
        ours, py, cpp = row.get("ours", {}), row.get("pyenki", {}), row.get("enki_cpp", {})
        overhead = ours.get("python_overhead_us_per_step")
        memory = " / ".join("—" if r.get("memory_per_world_kb") is None
                            else f"{r['memory_per_world_kb']:.0f}" for r in (ours, py, cpp))
        lines.append("| " + " | ".join([
            f"{worlds} × {robots}", _rate(ours.get("a_robot_steps_per_s")),
            _rate(ours.get("b_robot_steps_per_s")),
            "—" if overhead is None else f"{overhead:.1f}",
            f"{_rate(py.get('a_robot_steps_per_s'))} / {_rate(py.get('b_robot_steps_per_s'))}",
            _rate(cpp.get("a_robot_steps_per_s")),
            _ratio(ours.get("a_robot_steps_per_s"), cpp.get("a_robot_steps_per_s")),
            _ratio(ours.get("b_robot_steps_per_s"), py.get("b_robot_steps_per_s")),
            memory]) + " |")
    return "\n".join(lines)


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--robot-steps", type=float, default=2e6,
                        help="robot-steps timed per configuration, ours and Enki C++")
    parser.add_argument("--peer-robot-steps", type=float, default=5e4,
                        help="robot-steps timed per configuration for pyenki")
    parser.add_argument("--peers", default="ours,pyenki,enki_cpp,swarm",
                        help="comma-separated subset of ours, pyenki, enki_cpp, swarm")
    parser.add_argument("--configs", default=",".join(f"{b}x{r}" for b, r in CONFIGS),
                        help="comma-separated BxR configurations (worlds x robots)")
    parser.add_argument("--cpu", type=int, default=min(os.sched_getaffinity(0)),
                        help="the one CPU every measurement runs on")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--json", action="store_true", help="also print one JSON line a record")
    parser.add_argument("--worker", choices=sorted(WORKERS), help=argparse.SUPPRESS)
    parser.add_argument("--worlds", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--robots", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--steps", type=int, help=argparse.SUPPRESS)
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if args.worker:
        print(json.dumps(WORKERS[args.worker](args.worlds, args.robots, args.steps, args.seed)))
        return
    os.sched_setaffinity(0, {args.cpu})      # the children inherit it
    print(f"Machine: {machine()}", flush=True)
    records = []
    configs = [tuple(int(v) for v in c.split("x")) for c in args.configs.split(",")]
    for worlds, robots in configs:
        for peer in args.peers.split(","):
            if peer == "swarm" and robots > learn_swarm.MAX_ROBOTS:
                continue
            budget = args.peer_robot_steps if peer == "pyenki" else args.robot_steps
            steps = max(10, round(budget / (worlds * robots)))
            record = in_child(peer, worlds, robots, steps, args.seed)
            records.append(record)
            if args.json:
                print(json.dumps(record), flush=True)
    others = [r for r in records if r["peer"] != "swarm"]
    if others:
        print(markdown_table(others))
    swarm = learn_swarm.swarm_table(records, _rate)
    if swarm:
        print("\n" + swarm)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Enki as the benchmark peer: N e-pucks avoiding obstacles in a walled square arena.

Measures Enki's real-time factor (simulated seconds / wall seconds) and the peak resident
memory of the process, for comparison with epuck_vrep_compat on the same machine.

What is being timed, so the comparison stays honest:
- ``pyenki.World.step(dt)`` with Enki's default single physics pass per step.
- Every robot is a ``pyenki.EPuck``. Debian's binding always builds it with
  CAPABILITY_BASIC_SENSORS|CAPABILITY_CAMERA, so Enki also renders the 60-pixel linear camera
  every step; Python cannot switch that off.
- ``--controller braitenberg``: the obstacle avoidance runs in Python, in an overridden
  ``controlStep`` that Enki calls for each robot during ``World.step``. That is how a pyenki
  user writes a controller, so its cost is part of what a pyenki user pays.
- ``--controller none``: plain ``pyenki.EPuck`` robots with constant wheel speeds, to report
  Enki's physics and sensing alone. The binding still looks up a Python ``controlStep``
  override for every robot every step; that lookup cannot be avoided from Python.
- ``--controller both``: runs each mode in its own child process, so each peak memory figure
  belongs to one run, and prints one JSON line per run.

Enki works in centimetres; this script speaks metres and converts once, at the boundary.
"""

import argparse
import json
import math
import random
import resource
import subprocess
import sys
import time

_PROCESS_START_S = time.perf_counter()   # start-up is timed from here, before pyenki loads

import pyenki  # noqa: E402 (timed: importing the binding is part of a pyenki user's start-up)

CM_PER_M = 100.0
CELL_SIDE_M = 0.30      # one robot per cell, as in run_benchmark.py and enki_swarm
ARENA_MARGIN_M = 0.10
EPUCK_MAX_SPEED_M_S = 0.128

# Braitenberg avoidance. x_i = min(ir_i / IR_SATURATION, 1) is the activation of sensor i.
# Enki's e-puck IR value falls steeply with distance (about 3000 at 0.7 cm, 500 at 2.3 cm,
# 20 at 11 cm), so activation saturates at 300 (about 3 cm). Each wheel turns at
#   v = CRUISE_SPEED + AVOID_GAIN * sum_i W[i] * x_i   (m/s), clamped to the motor limit.
# Sensors are numbered clockwise from front-right (0) to front-left (7): an obstacle on the
# right slows the left wheel and speeds the right one, so the robot turns away from it. The
# front-left weights are slightly larger so a head-on obstacle still produces a turn. Tuned on
# 9 robots over 60 s: 6-8 % of samples touch a wall, against 95 % with constant speeds.
IR_SATURATION = 300.0
CRUISE_SPEED_M_S = 0.08
AVOID_GAIN_M_S = 0.4
LEFT_WHEEL_WEIGHTS = (-1.0, -0.8, -0.4, 0.0, 0.0, 0.4, 0.8, 1.2)
RIGHT_WHEEL_WEIGHTS = (1.0, 0.8, 0.4, 0.0, 0.0, -0.4, -0.8, -1.2)
CONTROLLERS = ("braitenberg", "none")


def clamp_speed_m_s(speed_m_s):
    """Limit a wheel speed to the e-puck's motor range."""
    return max(-EPUCK_MAX_SPEED_M_S, min(EPUCK_MAX_SPEED_M_S, speed_m_s))


def braitenberg_speeds_m_s(ir_values):
    """Left and right wheel speeds (m/s) from the eight raw IR values."""
    left = right = 0.0
    for value, w_left, w_right in zip(ir_values, LEFT_WHEEL_WEIGHTS, RIGHT_WHEEL_WEIGHTS):
        x = min(value / IR_SATURATION, 1.0)
        left += w_left * x
        right += w_right * x
    return (clamp_speed_m_s(CRUISE_SPEED_M_S + AVOID_GAIN_M_S * left),
            clamp_speed_m_s(CRUISE_SPEED_M_S + AVOID_GAIN_M_S * right))


class BraitenbergEPuck(pyenki.EPuck):
    """An e-puck whose Python controlStep turns its IR readings into wheel speeds."""

    def controlStep(self, dt):  # noqa: N802 (name fixed by pyenki)
        left_m_s, right_m_s = braitenberg_speeds_m_s(self.proximitySensorValues)
        self.leftSpeed = left_m_s * CM_PER_M
        self.rightSpeed = right_m_s * CM_PER_M


def arena_side_m(robot_count, cell_m=CELL_SIDE_M):
    """Side of a square arena holding the robots on a grid, one cell_m cell each."""
    return cell_m * math.ceil(math.sqrt(robot_count)) + ARENA_MARGIN_M


def build_world(robot_count, controller, seed, cell_m=CELL_SIDE_M):
    """A walled square arena with robots on a grid, headings drawn from a seeded generator.

    Returns the world and its robots; the robots must stay referenced from Python because
    pyenki's World does not own the objects added to it.
    """
    side_m = arena_side_m(robot_count, cell_m)
    world = pyenki.World(side_m * CM_PER_M, side_m * CM_PER_M)
    world.setRandomSeed(seed)
    headings = random.Random(seed)
    per_row = math.ceil(math.sqrt(robot_count))
    robots = []
    for index in range(robot_count):
        robot = BraitenbergEPuck() if controller == "braitenberg" else pyenki.EPuck()
        row, column = divmod(index, per_row)
        x_m = ARENA_MARGIN_M / 2 + (column + 0.5) * cell_m
        y_m = ARENA_MARGIN_M / 2 + (row + 0.5) * cell_m
        robot.pos = (x_m * CM_PER_M, y_m * CM_PER_M)
        robot.angle = headings.uniform(-math.pi, math.pi)
        if controller == "none":
            robot.leftSpeed = robot.rightSpeed = CRUISE_SPEED_M_S * CM_PER_M
        world.addObject(robot)
        robots.append(robot)
    return world, robots


def run_steps(world, step_s, sim_s):
    """Advance the world by sim_s simulated seconds; return the number of steps taken."""
    steps = max(1, round(sim_s / step_s))
    for _ in range(steps):
        world.step(step_s)
    return steps


def measure(robot_count, controller, step_s, sim_s, warmup_s, seed, cell_m=CELL_SIDE_M):
    """One timed run in this process; returns the result record. ``startup_s`` runs from the
    start of the process (before pyenki is imported) to the end of the first step."""
    world, _robots = build_world(robot_count, controller, seed, cell_m)
    world.step(step_s)
    startup_s = time.perf_counter() - _PROCESS_START_S
    run_steps(world, step_s, max(0.0, warmup_s - step_s))
    start = time.perf_counter()
    steps = run_steps(world, step_s, sim_s)
    wall_s = time.perf_counter() - start
    timed_sim_s = steps * step_s
    peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB on Linux
    return {
        "peer": "enki",
        "controller": controller,
        "robots": robot_count,
        "step_s": step_s,
        "sim_s": round(timed_sim_s, 9),
        "warmup_s": warmup_s,
        "wall_s": round(wall_s, 6),
        "rtf": round(timed_sim_s / wall_s, 6),
        "startup_s": round(startup_s, 6),
        "peak_rss_mb": round(peak_kib / 1024.0, 1),
        "arena_side_m": round(arena_side_m(robot_count, cell_m), 3),
        "cell_m": cell_m,
        "seed": seed,
    }


def run_in_child(args, controller):
    """Run one controller mode in a fresh interpreter so its peak memory is its own."""
    command = [sys.executable, __file__, "--robots", str(args.robots),
               "--sim-seconds", str(args.sim_seconds), "--warmup-seconds", str(args.warmup_seconds),
               "--step", str(args.step), "--seed", str(args.seed), "--cell-m", str(args.cell_m),
               "--controller", controller, "--json"]
    output = subprocess.run(command, check=True, stdout=subprocess.PIPE, text=True).stdout
    return json.loads(output)


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--robots", type=int, default=1, help="number of e-pucks (N)")
    parser.add_argument("--sim-seconds", type=float, default=20.0,
                        help="simulated time that is timed (s)")
    parser.add_argument("--warmup-seconds", type=float, default=1.0,
                        help="simulated time run before timing starts (s)")
    parser.add_argument("--step", type=float, default=0.01, help="simulation step (s)")
    parser.add_argument("--controller", choices=CONTROLLERS + ("both",), default="braitenberg",
                        help="Python Braitenberg controller, none (constant speeds), or both")
    parser.add_argument("--cell-m", type=float, default=CELL_SIDE_M,
                        help="side of each robot's square cell on the start grid (m)")
    parser.add_argument("--seed", type=int, default=1, help="seed for headings and Enki's noise")
    parser.add_argument("--json", action="store_true", help="print one JSON line per run")
    args = parser.parse_args(argv)
    if args.robots < 1:
        parser.error("--robots must be at least 1")
    if args.step <= 0.0 or args.sim_seconds <= 0.0 or args.warmup_seconds < 0.0 \
            or args.cell_m <= 0.0:
        parser.error("--step, --sim-seconds and --cell-m must be positive, --warmup-seconds "
                     "not negative")
    return args


def main(argv=None):
    args = parse_args(argv)
    if args.controller == "both":
        results = [run_in_child(args, controller) for controller in CONTROLLERS]
    else:
        results = [measure(args.robots, args.controller, args.step, args.sim_seconds,
                           args.warmup_seconds, args.seed, args.cell_m)]
    for result in results:
        if args.json:
            print(json.dumps(result), flush=True)
        else:
            print("enki {controller:<11} N={robots:<5} rtf={rtf:10.3f} wall={wall_s:.2f}s "
                  "startup={startup_s:.3f}s peak={peak_rss_mb} MB".format(**result), flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Instructions per robot-step of ``BatchedWorlds.step``, counted by callgrind: a measure of the
learning worlds' step that a loaded machine does not disturb (wall time does).

Builds the learning benchmark's worlds (bench/learn_bench.py: B worlds of R robots, noise off,
its seeded commands), steps them --warmup times, then --steps times under callgrind's
collection, which this script switches on around those steps alone (``valgrind
--collect-atstart=no`` and ``callgrind_control``-free: the toggle is the one function
``BatchedWorlds::step``). So the count is the C++ step's, without Python, building or warm-up:

    valgrind --tool=callgrind --collect-atstart=no \\
        --toggle-collect='evc::BatchedWorlds::step*' --callgrind-out-file=/tmp/cg.%p \\
        /usr/bin/python3 bench/step_instructions.py --worlds 100 --robots 10
    callgrind_annotate /tmp/cg.<pid> | head -40     # the total and where it goes

Divide the total by steps x B x R for instructions per robot-step; the script prints that
divisor. Without valgrind it just steps (a smoke test).
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import learn_bench  # noqa: E402 (beside this script: the benchmark's worlds)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worlds", type=int, default=100)
    parser.add_argument("--robots", type=int, default=10)
    parser.add_argument("--warmup", type=int, default=20)
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    core = learn_bench.build_ours(args.worlds, args.robots, args.seed)
    commands = learn_bench.command_table(args.worlds, args.robots, args.seed)
    for i in range(args.warmup):
        core.step(learn_bench.STEP_S, commands[i % len(commands)])
    for i in range(args.steps):
        core.step(learn_bench.STEP_S, commands[(args.warmup + i) % len(commands)])
    print(f"robot-steps counted: {args.steps * args.worlds * args.robots}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Instructions per robot-step of ``BatchedWorlds.step``, counted by callgrind: a measure of the
learning worlds' step that a loaded machine does not disturb (wall time does).

Builds the learning benchmark's worlds (bench/learn_bench.py: B worlds of R robots, noise off,
its seeded commands), steps them --warmup times, then --steps times. Callgrind counts the
instructions inside ``BatchedWorlds::step`` alone (``--toggle-collect``), so neither Python
nor building the worlds counts; warm-up steps do, so count twice, with ``--steps 0`` and with
``--steps 50``, and divide the difference by 50 x B x R for instructions per robot-step:

    valgrind --tool=callgrind --collect-atstart=no \\
        --toggle-collect='evc::BatchedWorlds::step*' --callgrind-out-file=/tmp/cg.%p \\
        /usr/bin/python3 bench/step_instructions.py --worlds 100 --robots 10 --steps 50
    callgrind_annotate /tmp/cg.<pid> | head -40     # the total and where it goes

Add ``--cache-sim=yes --branch-sim=yes --D1=49152,12,64 --LL=2097152,16,64`` for cache misses
(L1d and this machine's 2 MiB L2 as the last level) and branch mispredictions, which tell more
than instructions where a step waits on memory (docs/benchmarks.md, "Learning").

Count over the benchmark's own window (``--seed 1 --warmup 6`` and ``--steps`` of 2e6 robot-steps:
2000 at 100 x 10): the default 20 + 50 steps are the first seconds, before the robots have
driven into the walls, and count a fifth of what a robot-step costs there (docs/benchmarks.md,
"Learning", issue 25's speed goal).

Instruction counts do not depend on the machine's load, unlike wall time. Without valgrind the
script just steps (a smoke test).
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
    print(f"{args.worlds} x {args.robots} robots stepped {args.warmup} + {args.steps} times "
          f"({args.steps * args.worlds * args.robots} robot-steps after the warm-up)")


if __name__ == "__main__":
    main()

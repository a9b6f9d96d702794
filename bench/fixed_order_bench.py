#!/usr/bin/python3
"""The order-fixed Python side of a learning step (geometry/fixed_order.py): the C library's
functions through ``epuck_vrep_compat._libm``'s C++ loops against the same functions through
Python's ``math`` element by element (the baseline, measured in the same run), in the three
places that use them per step: the neighbours' block (atan2, cos, sin), the follow task's
reward (exp) and the perceptron's tanh. Both give the same bits (test_reduction_order.py).

    /usr/bin/python3 bench/fixed_order_bench.py [--repeat 200] [--cpu 0]
"""
import argparse
import math
import os
import time

import numpy as np

import epuck_vrep_compat.geometry.fixed_order as fixed_order
from epuck_vrep_compat.learn.tasks import make_task
from epuck_vrep_compat.policy import neighbours


def cpu_ms(fn, repeat):
    """CPU time of one call [ms], the best of five rounds of ``repeat`` calls."""
    fn()
    best = math.inf
    for _ in range(5):
        start = time.process_time()
        for _ in range(repeat):
            fn()
        best = min(best, (time.process_time() - start) / repeat)
    return 1e3 * best


def cases(seed=0):
    rng = np.random.default_rng(seed)
    poses = rng.uniform(0.0, 1.0, (1000, 3))
    task = make_task("follow_leader", 3, False, False, 1000)
    wheels, contact = np.zeros((1000, 3, 2)), np.zeros((1000, 3), bool)
    obs, world_poses = np.zeros((1000, 3, task.layout.size)), rng.uniform(0.0, 1.0, (1000, 3, 3))
    sums = rng.uniform(-3.0, 3.0, (1000, 2))
    return {
        "neighbours' block, 100 worlds x 10 robots": lambda: neighbours.blocks(
            poses, 3, 0.5, groups=100),
        "follow reward, 1000 worlds x 3 robots": lambda: task.rewards(
            wheels, 1.0, obs, world_poses, contact),
        "perceptron's tanh, 1000 robots": lambda: fixed_order.libm(math.tanh, sums),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=200)
    parser.add_argument("--cpu", type=int, help="pin to this CPU")
    args = parser.parse_args()
    if args.cpu is not None:
        os.sched_setaffinity(0, {args.cpu})
    loops = dict(fixed_order._LOOPS)
    measured = {}
    for name, fn in cases().items():
        fixed_order._LOOPS.clear()
        fixed_order._LOOPS.update(loops)
        c = cpu_ms(fn, args.repeat)
        fixed_order._LOOPS.clear()                     # the baseline: math element by element
        p = cpu_ms(fn, args.repeat)
        measured[name] = (c, p)
    fixed_order._LOOPS.update(loops)
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"{os.cpu_count()} CPUs, numpy {np.__version__}, pinned to "
          f"{sorted(os.sched_getaffinity(0))}, load average at start {load}")
    print("| per step | C++ loops (_libm) ms | Python's math ms | speed-up |")
    print("| --- | ---: | ---: | ---: |")
    for name, (c, p) in measured.items():
        print(f"| {name} | {c:.3f} | {p:.3f} | {p / c:.1f}x |")


if __name__ == "__main__":
    main()

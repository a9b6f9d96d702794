#!/usr/bin/python3
"""Start-up cost of a client node: import time and peak memory of a thesis node's process.

Client nodes (the thesis's nodes, the examples, bag_to_csv) import ``epuck_vrep_compat`` for
their own modules only. Until the package's ``__init__`` became lazy it loaded the compiled
simulator core (``_core``: Bullet, Eigen, the binding) in every one of them. This measures both
in the same run, in fresh processes: "now" imports the node's module as the node does; "eager"
imports ``epuck_vrep_compat._core`` first, which is what the package's import did before.
Reports medians over ``--runs`` of wall time to import and of the process's peak RSS
(ru_maxrss), and their ratios. Needs a built, sourced workspace.
"""
import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time

MODULES = {   # the scripts' modules: a thesis node, an example node, the bag exporter
    "Irb (thesis)": "epuck_vrep_compat.thesis.joint_names",
    "follow_the_leader": "epuck_vrep_compat.nodes.follow_the_leader",
    "bag_to_csv": "epuck_vrep_compat.thesis.bag_export",
}
CHILD = """
import importlib, resource, sys, time
t0 = time.perf_counter()
if sys.argv[2] == "eager":
    importlib.import_module("epuck_vrep_compat._core")
importlib.import_module(sys.argv[1])
dt = time.perf_counter() - t0
print(dt, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, "epuck_vrep_compat._core" in sys.modules)
"""


def measure(module, mode, runs):
    times, rss = [], []
    for _ in range(runs):
        out = subprocess.run([sys.executable, "-c", CHILD, module, mode], capture_output=True,
                             text=True, check=True).stdout.split()
        times.append(float(out[0]))
        rss.append(int(out[1]) / 1024.0)
        core_loaded = out[2] == "True"
    return statistics.median(times), statistics.median(rss), core_loaded


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=15)
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python "
          f"{platform.python_version()}, {time.strftime('%Y-%m-%d')}")
    print(f"{'node':<20} {'import now':>11} {'eager':>8} {'ratio':>6}   "
          f"{'peak RSS now':>12} {'eager':>8} {'ratio':>6}  _core loaded now")
    results = {}
    for label, module in MODULES.items():
        t_now, m_now, core_now = measure(module, "now", args.runs)
        t_old, m_old, _ = measure(module, "eager", args.runs)
        results[label] = dict(module=module, import_s=t_now, import_eager_s=t_old,
                              rss_mb=m_now, rss_eager_mb=m_old, core_loaded=core_now)
        print(f"{label:<20} {t_now * 1e3:>9.1f}ms {t_old * 1e3:>6.1f}ms {t_old / t_now:>6.2f}   "
              f"{m_now:>10.1f}MB {m_old:>6.1f}MB {m_old / m_now:>6.2f}  {core_now}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""The experiment runner against the way users run many simulations today, in one script.

Measures, on this machine, one after the other:
1. **Per-run overhead** at ``n:=1``: an experiment of ``--overhead-runs`` runs of one step each
   (the project's wander, one worker, so runs do not overlap); the mean wall time per run and
   where it goes (the rows' ``startup_s``: roslaunch, the master, the simulator and the code up,
   and the probe's ``start_grace_s``; ``stepping_s``; ``teardown_s``: roslaunch's shutdown
   until the last process is gone).
2. **Experiment 2** (``experiments/obstacle_avoidance.yaml``, its first ``--seeds`` seeds: 24
   runs of 30 simulated seconds a seed) with 1 and 2 local Dask workers, and with a scheduler
   and two workers started as separate processes (the cluster path): runs per hour, and the
   efficiency per worker (runs/h with k workers / (k × runs/h with 1)).
3. **The baseline**: what SIERRA and most lab scripts do: one ``roslaunch`` after another on
   the fixed port 11311, the simulator at its default real-time factor, each run ended after a
   fixed wall time (its simulated duration plus ``--baseline-margin`` seconds for start-up,
   as ``timeout`` would), then ``sleep --baseline-sleep`` seconds for the ports to be freed;
   the first ``--baseline-runs`` runs of experiment 2. Runs per hour, and our ratio to it.
Needs a built, sourced workspace and a machine to itself. Prints a table and a JSON line;
``--json FILE`` writes it.
"""
import argparse
import csv
import json
import os
import platform
import subprocess
import sys
import tempfile
import time

import yaml

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXPERIMENT_2 = os.path.join(REPO, "experiments", "obstacle_avoidance.yaml")
CLI = [sys.executable, os.path.join(REPO, "scripts", "experiment")]
VENV_BIN = os.path.join(REPO, ".venv", "bin")


def machine():
    model = ""
    with open("/proc/cpuinfo") as f:
        model = next((line.split(":", 1)[1].strip() for line in f
                      if line.startswith("model name")), "")
    with open("/proc/meminfo") as f:
        mem_kb = int(next(line.split()[1] for line in f if line.startswith("MemTotal")))
    return {"cpu": model, "cores": os.cpu_count(), "memory_gib": round(mem_kb / 2 ** 20, 1),
            "python": platform.python_version(), "os": platform.platform()}


def run_cli(args):
    started = time.monotonic()
    proc = subprocess.run(CLI + args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    elapsed = time.monotonic() - started
    if proc.returncode not in (0, 1):
        sys.exit(f"experiment {' '.join(args)} failed ({proc.returncode}):\n{proc.stdout[-3000:]}")
    return elapsed


def rows(out):
    with open(os.path.join(out, "results.csv")) as f:
        return list(csv.DictReader(f))


def overhead(work, runs):
    spec = {"name": "overhead", "simulator": {"args": {"n": 1, "cmd_vel_scaling": "si"}},
            "code": [{"name": "wander", "node": "epuck_vrep_compat/wander",
                      "params": {"robot": "ePuck0"}}],
            "seeds": runs, "duration_s": 0.05, "pace": {"wait_for": ["/ePuck0/cmd_vel"]},
            "metrics": ["distance_driven"]}
    path = os.path.join(work, "overhead.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(spec, f)
    out = os.path.join(work, "overhead")
    elapsed = run_cli(["run", path, "--out", out, "--workers", "1"])
    table = rows(out)
    mean = {k: sum(float(r[k]) for r in table) / len(table)
            for k in ("wall_s", "startup_s", "stepping_s", "teardown_s")}
    return {"runs": len(table), "ok": sum(r["status"] == "ok" for r in table),
            "elapsed_s": round(elapsed, 1), **{k: round(v, 3) for k, v in mean.items()},
            "start_grace_s": 0.5}


def ours(work, label, seeds, extra):
    out = os.path.join(work, label)
    elapsed = run_cli(["run", EXPERIMENT_2, "--out", out, "--seeds", str(seeds)] + extra)
    table = rows(out)
    return {"runs": len(table), "ok": sum(r["status"] == "ok" for r in table),
            "elapsed_s": round(elapsed, 1), "runs_per_hour": round(len(table) / elapsed * 3600)}


def with_remote_cluster(work, seeds, workers=2):
    """Experiment 2 through a scheduler and workers started as their own processes."""
    scheduler_file = os.path.join(work, "scheduler.json")
    env = dict(os.environ)
    procs = [subprocess.Popen([os.path.join(VENV_BIN, "dask"), "scheduler", "--host",
                               "127.0.0.1", "--port", "0", "--no-dashboard", "--scheduler-file",
                               scheduler_file], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, start_new_session=True)]
    try:
        deadline = time.monotonic() + 60
        while not os.path.isfile(scheduler_file) and time.monotonic() < deadline:
            time.sleep(0.2)
        with open(scheduler_file) as f:
            address = json.load(f)["address"]
        procs.append(subprocess.Popen(
            [os.path.join(VENV_BIN, "dask"), "worker", address, "--nworkers", str(workers),
             "--nthreads", "1", "--no-dashboard"], env=env, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL, start_new_session=True))
        return ours(work, "remote", seeds, ["--scheduler", address])
    finally:
        for p in reversed(procs):
            os.killpg(p.pid, 2)
            try:
                p.wait(30)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, 9)


def baseline(work, runs, margin_s, sleep_s):
    """One roslaunch after another, fixed port, fixed wall time, a sleep between."""
    sys.path.insert(0, os.path.join(REPO, "python"))
    from epuck_vrep_compat.experiment import plan, spec as spec_mod
    tasks = plan.tasks(spec_mod.load(EXPERIMENT_2))[:runs]
    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:11311", ROS_IP="127.0.0.1",
               ROS_HOME=os.path.join(work, "baseline_ros_home"))
    started = time.monotonic()
    for task in tasks:
        args = dict(task.sim_args, rtf=1.0, paused=False)
        student = task.code[0]
        text = ["<launch>", f'  <include file="{task.sim_launch}">']
        text += [f'    <arg name="{k}" value="{v}"/>' for k, v in sorted(args.items())]
        text += ["  </include>", f'  <include file="{student["launch"]}">']
        text += [f'    <arg name="{k}" value="{v}"/>' for k, v in student["args"].items()]
        text += ["  </include>", "</launch>"]
        path = os.path.join(work, "baseline.launch")
        with open(path, "w") as f:
            f.write("\n".join(text) + "\n")
        subprocess.run(["timeout", "-s", "INT", "-k", "20", str(task.duration_s + margin_s),
                        "roslaunch", "-p", "11311", path], env=env, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        time.sleep(sleep_s)
    elapsed = time.monotonic() - started
    return {"runs": len(tasks), "elapsed_s": round(elapsed, 1),
            "runs_per_hour": round(len(tasks) / elapsed * 3600)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--overhead-runs", type=int, default=8)
    parser.add_argument("--seeds", type=int, default=1, help="experiment 2's seeds (24 runs each)")
    parser.add_argument("--baseline-runs", type=int, default=6)
    parser.add_argument("--baseline-margin", type=float, default=5.0)
    parser.add_argument("--baseline-sleep", type=float, default=2.0)
    parser.add_argument("--json")
    args = parser.parse_args()
    result = {"machine": machine()}
    with tempfile.TemporaryDirectory(prefix="experiment-bench-") as work:
        result["overhead"] = overhead(work, args.overhead_runs)
        result["workers_1"] = ours(work, "w1", args.seeds, ["--workers", "1"])
        result["workers_2"] = ours(work, "w2", args.seeds, ["--workers", "2"])
        result["remote_2"] = with_remote_cluster(work, args.seeds)
        result["baseline"] = baseline(work, args.baseline_runs, args.baseline_margin,
                                      args.baseline_sleep)
    one = result["workers_1"]["runs_per_hour"]
    result["efficiency_2_workers"] = round(result["workers_2"]["runs_per_hour"] / (2 * one), 2)
    result["ratio_to_baseline"] = round(result["workers_2"]["runs_per_hour"]
                                        / result["baseline"]["runs_per_hour"], 2)
    m, o = result["machine"], result["overhead"]
    print(f"machine: {m['cpu']}, {m['cores']} cores, {m['memory_gib']} GiB, Python {m['python']}")
    print(f"per-run overhead (n=1, one step): {o['wall_s']:.2f} s a run = startup "
          f"{o['startup_s']:.2f} (of which the probe's grace {o['start_grace_s']}) + stepping "
          f"{o['stepping_s']:.2f} + teardown {o['teardown_s']:.2f}; {o['ok']}/{o['runs']} ok")
    for key in ("workers_1", "workers_2", "remote_2", "baseline"):
        r = result[key]
        print(f"{key:10s} {r['runs']:4d} runs in {r['elapsed_s']:7.1f} s: "
              f"{r['runs_per_hour']:6d} runs/h")
    print(f"efficiency per worker (2): {result['efficiency_2_workers']}; ours (2 workers) / "
          f"baseline: {result['ratio_to_baseline']}x")
    print(json.dumps(result))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()

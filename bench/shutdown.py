#!/usr/bin/python3
"""Time from SIGINT to exit of the simulator with every topic subscribed, now and before.

For each N: a fresh master on a free port, the simulator (``rtf:=0``, the swarm benchmark's
arena: one robot per 0.30 m grid cell), one separate C++ process (``build/subscribe_all``,
``bench/build.sh``) subscribed to every topic of every robot and ``/tf``; once the simulator
lists a connection of it on every topic (``getBusInfo``), plus ``--settle-s`` of stepping, the
simulator gets SIGINT and the wall time until its process has exited is taken. roslaunch's
escalation is played as roslaunch plays it: SIGTERM 15 s after the SIGINT, SIGKILL 2 s after
that; a run it ended says so (``ended_by``). Also recorded: the exit status, any traceback or
``TypeError`` in its output, and how many of its registrations the master still holds after
(``left_registered``, once it forgot the node or after 30 s) and how long from the SIGINT it
took the master to forget the node (``master_forgot_s``: the simulator hands the withdrawal to
a process of its own and does not wait for it).

``--baseline-tree DIR`` runs the same measurement, in the same run, against another checkout
with its own built workspace (``DIR/.ws``, made by ``tools/setup`` there), e.g. a
``git worktree`` of the commit before: the rows then show both, ``tree`` saying which. The
subscriber is this checkout's in both. Needs a built, sourced workspace and ``bench/build.sh``.

    bench/shutdown.py --robots 10 100 1000 --runs 3 --baseline-tree ../before --json stop.jsonl
"""
import argparse
import json
import os
import platform
import re
import signal
import statistics
import subprocess
import tempfile
import time

import rosgraph

from run_benchmark import (HERE, PROFILE_TOPICS, SIM_NODE, free_port, robots_registered,
                           scene_file, wait_connected)

SIGTERM_AFTER_S = 15.0     # roslaunch's _TIMEOUT_SIGINT
SIGKILL_AFTER_S = 2.0      # roslaunch's _TIMEOUT_SIGTERM
MASTER_WAIT_S = 30.0       # how long to watch the master forget the stopped simulator
REPO = os.path.dirname(HERE)
# the simulator of a given tree, in that tree's workspace
LAUNCH_IN_TREE = 'source "$0/.ws/devel/setup.bash" && exec rosrun epuck_vrep_compat epuck_sim "$@"'


def wait_for(condition, timeout_s, period_s=0.05):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            if condition():
                return True
        except (OSError, rosgraph.MasterException):
            pass
        time.sleep(period_s)
    return False


def registrations_of(master, node):
    """How many topics and services the master lists ``node`` for (1 more while it knows the
    node at all, through a parameter subscription alone)."""
    state = master.getSystemState()
    held = sum(node in nodes for kind in state for _name, nodes in kind)
    try:
        master.lookupNode(node)
        return held + 1
    except rosgraph.MasterError:
        return held


def wait_forgotten(master, node, since, timeout_s=MASTER_WAIT_S):
    """Seconds from ``since`` until the master forgets ``node`` (None: not within
    ``timeout_s``), and what it still holds then."""
    forgotten = wait_for(lambda: registrations_of(master, node) == 0, timeout_s, 0.02)
    return (round(time.monotonic() - since, 3) if forgotten else None,
            registrations_of(master, node))


def stop_and_time(sim, started):
    """SIGINT at ``started``, then roslaunch's escalation; (seconds to exit, the signal that
    ended it)."""
    sim.send_signal(signal.SIGINT)
    ended_by = "SIGINT"
    for sig, after_s in ((signal.SIGTERM, SIGTERM_AFTER_S), (signal.SIGKILL, SIGKILL_AFTER_S)):
        try:
            sim.wait(timeout=after_s)
            break
        except subprocess.TimeoutExpired:
            sim.send_signal(sig)
            ended_by = sig.name
    sim.wait()
    return time.monotonic() - started, ended_by


def run_once(tree, n, settle_s):
    """One start, subscription and stop at N robots with ``tree``'s simulator."""
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}")
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    master_proc = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    world = scene_file(n, 0.30)
    log = tempfile.TemporaryFile("w+")
    sim = sub = None
    _cmd, regex, robot_topic = PROFILE_TOPICS["vrep"]
    try:
        master = rosgraph.Master("/bench_shutdown")
        wait_for(master.is_online, 30.0)
        sim = subprocess.Popen(["bash", "-c", LAUNCH_IN_TREE, tree, f"_n:={n}",
                                f"_world:={world}", "_rtf:=0.0"], env=env, stdout=log,
                               stderr=subprocess.STDOUT, start_new_session=True)
        wait_for(lambda: robots_registered(master, n, re.compile(robot_topic)), 600.0, 0.2)
        sub = subprocess.Popen([os.path.join(HERE, "build", "subscribe_all"), "--regex", regex],
                               env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               start_new_session=True)
        connected, expected = wait_connected(SIM_NODE, regex, 60.0 + n / 10.0)
        time.sleep(settle_s)
        started = time.monotonic()
        stop_s, ended_by = stop_and_time(sim, started)
        forgotten_s, left = wait_forgotten(master, SIM_NODE, started)
        log.seek(0)
        output = log.read()
        return {"robots": n, "stop_s": round(stop_s, 3), "ended_by": ended_by,
                "exit_status": sim.returncode, "traceback": "Traceback" in output,
                "type_error": "TypeError" in output,
                "master_forgot_s": forgotten_s, "left_registered": left,
                "connected_topics": connected, "subscribed_topics": expected}
    finally:
        for p in (sub, sim):
            if p is not None and p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()
        master_proc.terminate()
        master_proc.wait(timeout=30)
        log.close()
        os.unlink(world)


def summary(rows):
    """One line per tree and N: the median and the worst of the runs."""
    lines = [f"{'tree':<9} {'N':>5} {'exit s: median':>14} {'max':>6}  {'master forgot s':>15}  "
             "ended by (runs)  exit status  tracebacks  left registered"]
    for tree in dict.fromkeys(r["tree"] for r in rows):
        for n in dict.fromkeys(r["robots"] for r in rows):
            runs = [r for r in rows if r["tree"] == tree and r["robots"] == n]
            if not runs:
                continue
            times = [r["stop_s"] for r in runs]
            forgot = [r["master_forgot_s"] for r in runs if r["master_forgot_s"] is not None]
            forgot_text = f"{statistics.median(forgot):.2f}" if forgot else "never"
            lines.append(f"{tree:<9} {n:>5} {statistics.median(times):>14.2f} {max(times):>6.2f}  "
                         f"{forgot_text:>15}  "
                         f"{', '.join(sorted({r['ended_by'] for r in runs}))} ({len(runs)})  "
                         f"{sorted({r['exit_status'] for r in runs})}  "
                         f"{sum(r['traceback'] or r['type_error'] for r in runs)}  "
                         f"{max(r['left_registered'] for r in runs)}")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robots", type=int, nargs="+", default=[10, 100, 1000])
    ap.add_argument("--runs", type=int, default=3, help="stops per tree and N")
    ap.add_argument("--settle-s", type=float, default=5.0,
                    help="wall seconds of stepping, everything connected, before the SIGINT")
    ap.add_argument("--baseline-tree", help="another checkout with a built .ws, measured too")
    ap.add_argument("--json", help="append JSON lines here")
    args = ap.parse_args()
    trees = {"now": REPO}
    if args.baseline_tree:
        trees["baseline"] = os.path.abspath(args.baseline_tree)
    for path in trees.values():
        if not os.path.exists(os.path.join(path, ".ws", "devel", "setup.bash")):
            ap.error(f"{path} has no built workspace (run bash tools/setup there)")
    print(" ".join(f"{label}: {path}" for label, path in trees.items()))
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"{time.strftime('%Y-%m-%d %H:%M')}", flush=True)
    rows = []
    for n in args.robots:
        for run in range(args.runs):
            for label, path in trees.items():   # interleaved: drift hits both alike
                row = run_once(path, n, args.settle_s)
                row.update(tree=label, path=path, run=run)
                rows.append(row)
                print(json.dumps(row), flush=True)
                if args.json:
                    with open(args.json, "a") as f:
                        f.write(json.dumps(row) + "\n")
    print(summary(rows))


if __name__ == "__main__":
    main()

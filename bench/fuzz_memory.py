#!/usr/bin/python3
"""Where the simulator's memory settles under a long ``/vrep`` fuzz (issue 27).

Runs the suite's ``/vrep`` fuzz tests (``test/rostest/test_vrep_fuzz.py``: the very requests,
modes and checks of ``vrep_fuzz.test`` and ``vrep_fuzz_cell.test``, imported, not copied)
``--rounds`` times in a row (10 by default: ten times what the suite sends) against the scene
of each of those launch files, each started by ``roslaunch`` on a master of its own. Every
``--every`` calls it samples the simulator's resident memory (``VmRSS``), threads and
descriptors; it writes ``fuzz_memory.csv`` and ``fuzz_memory.png`` into ``--out`` and prints,
per scene, the memory at the end of each round and the growth over the last half of the rounds
(memory that settles grows by next to nothing there). Wall times are rough on a shared machine;
the memory figures are what counts. Needs a built workspace, sourced.

    bench/fuzz_memory.py --rounds 10 --out results/fuzz_memory
    bench/fuzz_memory.py --scenes cell --rounds 2 --tests test_01 test_13
"""
import argparse
import csv
import os
import signal
import subprocess
import sys
import time
import unittest

from run_benchmark import free_port     # bench/: one free port finder

HERE = os.path.dirname(os.path.abspath(__file__))
ROSTEST_DIR = os.path.join(HERE, "..", "test", "rostest")
SCENES = {"epucks": "vrep_fuzz.test", "cell": "vrep_fuzz_cell.test"}
SETTLE_S = 3.0      # after a round, before its last sample: closed connections' threads end
FIELDS = ("scene", "round", "test", "calls", "wall_s", "rss_mb", "threads", "fds", "service")


# put first on the simulator's PYTHONPATH by --tracemalloc: Python's allocations traced in the
# simulator (and only there), a snapshot dumped on each SIGUSR2 (the driver sends one per round)
TRACEMALLOC_HOOK = """import os
if b"epuck_sim" in open("/proc/self/cmdline", "rb").read():
    import signal, tracemalloc
    tracemalloc.start(1)
    def _dump(signum, frame, _n=[0]):
        tracemalloc.take_snapshot().dump(os.path.join(os.path.dirname(__file__),
                                                      f"snapshot_{_n[0]:02d}.pickle"))
        _n[0] += 1
    signal.signal(signal.SIGUSR2, _dump)
"""


def process_figures(pid):
    """(RSS in MB, threads, open descriptors) of a process."""
    rss_mb, threads = 0.0, 0
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                rss_mb = int(line.split()[1]) / 1024.0
            elif line.startswith("Threads:"):
                threads = int(line.split()[1])
    return rss_mb, threads, len(os.listdir(f"/proc/{pid}/fd"))


# --- the driver: a process of its own per scene (rospy talks to one master per process) -------
def drive(args):
    """Runs the fuzz suite ``args.rounds`` times, sampling the simulator every ``args.every``
    calls into ``args.csv``."""
    import rosgraph
    import xmlrpc.client
    sys.path.insert(0, ROSTEST_DIR)
    import test_vrep_fuzz as fuzz

    master = rosgraph.Master("/fuzz_memory")
    deadline = time.monotonic() + 120
    while True:
        try:
            pid = xmlrpc.client.ServerProxy(master.lookupNode("/vrep")).getPid("/fuzz_memory")[2]
            break
        except Exception:  # noqa: BLE001 - not up yet
            if time.monotonic() > deadline:
                raise
            time.sleep(0.5)
    t0, state = time.monotonic(), {"calls": 0, "round": 0, "test": "", "service": ""}
    out = open(args.csv, "a", newline="")
    writer = csv.writer(out)

    def sample():
        writer.writerow([args.scene, state["round"], state["test"], state["calls"],
                         f"{time.monotonic() - t0:.1f}",
                         *(f"{v:.1f}" if isinstance(v, float) else v
                           for v in process_figures(pid)), state["service"]])
        out.flush()

    class CountingCaller(fuzz.Caller):
        def __call__(self, service, *a, **kw):
            state["calls"] += 1
            if state["calls"] % args.every == 0:
                sample()
            state["service"] = service.rsplit("/", 1)[-1]
            return super().__call__(service, *a, **kw)
    fuzz.Caller = CountingCaller

    class NamingResult(unittest.TextTestResult):
        def startTest(self, test):
            state["test"] = test.id().split(".")[-1]
            super().startTest(test)
    sample()
    objects = scene_objects(fuzz, args.scene)
    if args.tracemalloc:
        os.kill(pid, signal.SIGUSR2)
    failed = 0
    for k in range(args.rounds):
        state["round"] = k + 1
        suite = unittest.TestLoader().loadTestsFromTestCase(fuzz.VrepFuzz)
        if args.tests:
            suite = unittest.TestSuite(t for t in suite if any(
                t.id().split(".")[-1].startswith(p) for p in args.tests))
        result = unittest.TextTestRunner(stream=open(os.devnull, "w"), verbosity=0,
                                         resultclass=NamingResult).run(suite)
        failed += len(result.failures) + len(result.errors)
        for test, trace in result.failures + result.errors:
            name = test.id().split(".")[-1]
            print(f"{args.scene} round {k + 1}: {name} failed: "
                  f"{trace.strip().splitlines()[-1][:300]}", flush=True)
            with open(args.csv[:-len(".csv")] + f"_failures_{args.scene}.txt", "a") as f:
                f.write(f"--- round {k + 1}: {name}\n{trace}\n")
        time.sleep(SETTLE_S)
        sample()
        if args.tracemalloc:
            os.kill(pid, signal.SIGUSR2)
        now = scene_objects(fuzz, args.scene)
        print(f"{args.scene} round {k + 1}: {state['calls']} calls, "
              f"{process_figures(pid)[0]:.1f} MB, {len(result.failures) + len(result.errors)} "
              f"failed tests; {len(now)} scene objects, gone since the start: "
              f"{sorted(set(objects) - set(now)) or 'none'}", flush=True)
    out.close()
    return 1 if failed else 0


def set_test_params(rospy, launch):
    """The private parameters the launch file gives its fuzz test (as rostest would)."""
    import xml.etree.ElementTree as ET
    for test in ET.parse(launch).getroot().iter("test"):
        for p in test.iter("param"):
            text = p.get("value")
            value = {"true": True, "false": False}.get(text.lower(), text)
            rospy.set_param("~" + p.get("name"), value)


def scene_objects(fuzz, scene):
    """The scene's object names (the suite removes some of them, so later rounds run on a
    smaller scene)."""
    import rospy
    import vrep_common.srv as srv
    rospy.init_node("test_vrep_fuzz")    # the suite's own node name: it calls init_node again
    set_test_params(rospy, os.path.join(ROSTEST_DIR, SCENES[scene]))
    rospy.wait_for_service("/vrep/simRosGetObjectGroupData", timeout=120)  # after its pid
    proxy = rospy.ServiceProxy("/vrep/simRosGetObjectGroupData", srv.simRosGetObjectGroupData)
    try:
        return proxy(objectType=fuzz.ALL_OBJECTS, dataType=0).strings
    finally:
        proxy.close()


# --- the parent: a simulator per scene, the driver against it, the figures ---------------------
def run_scene(scene, args, csv_path):
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}",
               ROS_LOG_DIR=os.path.join(args.out, "logs", scene))
    if args.tracemalloc:
        hook = os.path.abspath(os.path.join(args.out, "tracemalloc", scene))
        os.makedirs(hook, exist_ok=True)
        with open(os.path.join(hook, "sitecustomize.py"), "w") as f:
            f.write(TRACEMALLOC_HOOK)
        env["PYTHONPATH"] = hook + os.pathsep + env.get("PYTHONPATH", "")
    launch = os.path.join(ROSTEST_DIR, SCENES[scene])
    # roslaunch starts the master of the port, in its own process group with the simulator
    sim = subprocess.Popen(["roslaunch", "-p", str(port), launch], env=env,
                           stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT,
                           start_new_session=True)
    try:
        command = [sys.executable, os.path.abspath(__file__), "--drive", "--scene", scene,
                   "--rounds", str(args.rounds), "--every", str(args.every), "--csv", csv_path]
        if args.tests:
            command += ["--tests", *args.tests]
        if args.tracemalloc:
            command.append("--tracemalloc")
            env = dict(env, PYTHONPATH=env["PYTHONPATH"].split(os.pathsep, 1)[1])
        return subprocess.call(command, env=env)
    finally:
        try:                                 # our own process group only
            os.killpg(sim.pid, signal.SIGINT)
            sim.wait(30)
        except subprocess.TimeoutExpired:
            os.killpg(sim.pid, signal.SIGKILL)
            sim.wait()


def read_rows(csv_path):
    with open(csv_path) as f:
        return [r for r in csv.DictReader(f)]


def settling(rows):
    """Per scene: each round's highest RSS and its RSS at the end, and the growth of the
    highest over the last half of the rounds."""
    lines = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        mine = [r for r in rows if r["scene"] == scene]
        ends, peaks = {}, {}
        for r in mine:
            k, rss = int(r["round"]), float(r["rss_mb"])
            ends[k] = rss                                  # the last sample of each round
            peaks[k] = max(peaks.get(k, 0.0), rss)
        rounds = sorted(k for k in ends if k > 0) or [0]
        half = rounds[(len(rounds) - 1) // 2]
        lines.append(f"{scene}: start {float(mine[0]['rss_mb']):.1f} MB; per round highest "
                     + ", ".join(f"{peaks[k]:.1f}" for k in rounds) + " MB, at its end "
                     + ", ".join(f"{ends[k]:.1f}" for k in rounds) + " MB; highest "
                     f"{peaks[rounds[-1]] - peaks[half]:+.1f} MB from round {half} to "
                     f"{rounds[-1]} ({mine[-1]['calls']} calls, threads {mine[0]['threads']} -> "
                     f"{mine[-1]['threads']}, descriptors {mine[0]['fds']} -> {mine[-1]['fds']})")
    return lines


def growth_by_service(rows, top=8):
    """Per scene, from the second round on: the resident memory gained across each service's
    calls (a sample's ``service`` is the call just before it), summed, the largest first. Most
    telling with ``--every 1``."""
    lines = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        mine = [r for r in rows if r["scene"] == scene]
        gained = {}
        for before, after in zip(mine, mine[1:]):
            if int(after["round"]) >= 2 and after.get("service"):
                name = after["service"]
                gained[name] = gained.get(name, 0.0) + float(after["rss_mb"]) \
                    - float(before["rss_mb"])
        worst = sorted(gained.items(), key=lambda kv: -kv[1])[:top]
        if worst:
            lines.append(f"{scene}: memory gained across each service's calls from round 2 on: "
                         + ", ".join(f"{name} {mb:+.1f} MB" for name, mb in worst))
    return lines


def traced_growth(folder, scene, top=12):
    """What Python held more of after the last round than after the second (the first round
    fills what is filled once), by file and line."""
    import glob
    import tracemalloc
    snapshots = sorted(glob.glob(os.path.join(folder, "snapshot_*.pickle")))
    if len(snapshots) < 3:
        return [f"{scene}: fewer than 3 tracemalloc snapshots"]
    loaded = [tracemalloc.Snapshot.load(p) for p in snapshots]
    held = [sum(s.size for s in snap.statistics("filename")) / 2**20 for snap in loaded]
    lines = [f"{scene}: Python's traced memory " + ", ".join(f"{mb:.1f}" for mb in held)
             + " MB (start, then after each round); from round 2 to round "
             f"{len(snapshots) - 1}, the largest growths:"]
    first, last = loaded[2], loaded[-1]
    for stat in last.compare_to(first, "lineno")[:top]:
        lines.append(f"  {stat.size_diff / 1024:+.0f} KiB {stat.count_diff:+d} blocks "
                     f"{stat.traceback[0].filename}:{stat.traceback[0].lineno}")
    return lines


def plot(rows, png_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for scene in dict.fromkeys(r["scene"] for r in rows):
        mine = [r for r in rows if r["scene"] == scene]
        ax.plot([int(r["calls"]) for r in mine], [float(r["rss_mb"]) for r in mine],
                label=f"{scene} ({SCENES[scene]})")
    ax.set_xlabel("/vrep calls")
    ax.set_ylabel("simulator RSS [MB]")
    ax.set_title("The /vrep fuzz suite in a loop: the simulator's memory")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(png_path, dpi=100)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", nargs="+", choices=sorted(SCENES), default=list(SCENES))
    parser.add_argument("--rounds", type=int, default=10, help="runs of the fuzz suite")
    parser.add_argument("--every", type=int, default=100, help="calls between samples")
    parser.add_argument("--tests", nargs="*", default=[],
                        help="only the fuzz tests whose names start so (default: all)")
    parser.add_argument("--out", default="results/fuzz_memory")
    parser.add_argument("--replot", action="store_true",
                        help="only plot and summarise the CSV already in --out")
    parser.add_argument("--tracemalloc", action="store_true",
                        help="trace Python's allocations in the simulator (slower): a snapshot "
                        "per round, and what grew from the second round to the last by line")
    parser.add_argument("--drive", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--scene", help=argparse.SUPPRESS)
    parser.add_argument("--csv", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.drive:
        return drive(args)
    os.makedirs(args.out, exist_ok=True)
    csv_path = os.path.join(args.out, "fuzz_memory.csv")
    status = 0
    if not args.replot:
        with open(csv_path, "w", newline="") as f:
            csv.writer(f).writerow(FIELDS)
        for scene in args.scenes:
            status |= run_scene(scene, args, csv_path)
    if args.tracemalloc:
        for scene in args.scenes:
            print("\n".join(traced_growth(os.path.join(args.out, "tracemalloc", scene), scene)))
    rows = read_rows(csv_path)
    plot(rows, os.path.join(args.out, "fuzz_memory.png"))
    print("\n".join(settling(rows)))
    print("\n".join(growth_by_service(rows)))
    print(f"wrote {csv_path} and fuzz_memory.png" + ("" if status == 0 else
                                                       "; some fuzz tests failed (see above)"))
    return status


if __name__ == "__main__":
    sys.exit(main())

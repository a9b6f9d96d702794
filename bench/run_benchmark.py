#!/usr/bin/python3
"""Real-time factor, start-up time and peak memory of epuck_vrep_compat against Enki, in one run.

For each N: a square walled arena, one robot per ``--cell-m`` (0.30 m) square cell on a grid, N
e-pucks, noise on, every topic advertised, ``rtf:=0`` (as fast as possible), 50 ms step (V-REP's
default). Every robot gets one constant forward ``cmd_vel`` (watchdog off) and drives into walls
and neighbours, so collisions and IR cones are exercised. Scenarios: (a) nobody subscribed; (b)
one separate C++ process (``subscribe_all``) takes every topic of every robot and ``/tf``.
Memory is the simulator process's peak RSS (VmHWM). Start-up: from starting the simulator
process until every robot's topics are registered with the master (``topics_s``) and until the
first ``/clock`` message arrives (``first_step_s``); ``startup_s`` is the later of the two.

Peers, same arena and robots: Enki's C++ library driven from C++ (``build/enki_swarm``: 8 IR
sensors, Braitenberg avoidance in C++, no camera) at Enki's 10 ms step and at our 50 ms step,
its start-up timed from its process start to the end of its first step; and Debian's pyenki
(``enki_peer.py``: Python controller, a camera it cannot switch off) at 10 ms. The table's
ratios compare ours with Enki C++ at the same 50 ms step. With ``--floor``, the per-message floor
of (b): a bare roscpp process (``build/floor_sender``) advertising the same topics and publishing
the same messages flat out, with no simulation, to the same ``subscribe_all`` (roscpp writes
each message on its own; our writer coalesces a topic's messages, so it may beat this "floor").
Messages per second are counted over the measured window, which starts once the simulator
lists a connection of the subscriber on every subscribed topic (``getBusInfo``; recorded as
``connected_topics`` of ``subscribed_topics``).
The rows are profile ``vrep``'s; ``--epuck2-robots`` adds rows of profile ``epuck2_driver``
(its extra sensors: time-of-flight ray, magnetometer, battery, ground sensors, microphones,
their topics), by default at N = 100. Commands are SI (``cmd_vel_scaling:=si``) in both, so
the robots drive alike.
Requires a built workspace (``tools/setup``) sourced, and ``bench/build.sh`` run.

    bench/run_benchmark.py --robots 1 10 100 1000 --json results/bench.jsonl
"""
import argparse
import json
import math
import os
import platform
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
import xmlrpc.client

import numpy as np
import rosgraph
import rospy
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock

from bench_table import markdown_table
from epuck_vrep_compat.experiment.isolation import free_port

HERE = os.path.dirname(os.path.abspath(__file__))
CELL_SIDE_M = 0.30
ARENA_MARGIN_M = 0.10
SIM_NODE = "/vrep"
CONNECT_TIMEOUT_S = 60.0   # plus N / 10 s: how long (b) waits for every subscription to connect
# per profile: each robot's cmd_vel, the subscriber's regex, a robot's topics (index captured)
PROFILE_TOPICS = {"vrep": ("/ePuck{i}/cmd_vel", r"^/(ePuck\d+/.*|tf)$", r"^/ePuck(\d+)/"),
                  "epuck2_driver": ("/epuck_robot_{i}/mobile_base/cmd_vel",
                                    r"^/(epuck_robot_\d+/.*|tf)$", r"^/epuck_robot_(\d+)/")}


def end_group(proc, timeout_s):
    """SIGINT to a process started in a session of its own and everything it started (as
    Ctrl-C would), SIGKILL after ``timeout_s``; waits for it."""
    if proc is None or proc.poll() is not None:
        return
    os.killpg(proc.pid, signal.SIGINT)
    try:
        proc.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


def scene_file(n, cell_m, seed=1):
    """The arena Enki C++ gets (``enki_swarm.cpp``): square, walled, robot i at the centre of
    grid cell (i mod per_row, i div per_row), headings uniform in [-pi, pi) from a seeded
    generator. Without the starts, our simulator would pack the robots at 11.4 cm spacing into
    one corner (its default placement), a far denser and costlier arena than the peer's."""
    per_row = math.ceil(math.sqrt(n))
    side = cell_m * per_row + ARENA_MARGIN_M
    corner = -side / 2 + ARENA_MARGIN_M / 2
    headings = np.random.default_rng(seed).uniform(-math.pi, math.pi, n)
    lines = [f"arena:\n  size_m: [{side}, {side}]\nrobots:\n"]
    for i in range(n):
        row, column = divmod(i, per_row)
        lines.append(f"  - {{position_m: [{corner + (column + 0.5) * cell_m:.6f}, "
                     f"{corner + (row + 0.5) * cell_m:.6f}], yaw_rad: {headings[i]:.6f}}}\n")
    f = tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False)
    f.write("".join(lines))
    f.close()
    return f.name


def peak_rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


class ClockWatch:
    def __init__(self):
        self.sim_s = 0.0
        self.first_at = None
        rospy.Subscriber("/clock", Clock, self._cb, queue_size=1)

    def _cb(self, msg):
        if self.first_at is None:
            self.first_at = time.monotonic()
        self.sim_s = msg.clock.to_sec()

    def rtf_over(self, wall_s):
        s0, t0 = self.sim_s, time.monotonic()
        time.sleep(wall_s)
        return (self.sim_s - s0) / (time.monotonic() - t0)


def robots_registered(master, n, robot_topic):
    """True once every robot has as many topics (published and subscribed by the simulator)
    registered with the master as the robot with the most, and that is at least nine (eight
    ranges and the IMU)."""
    publishers, subscribers, _services = master.getSystemState()
    counts = [0] * n
    for topic, nodes in publishers + subscribers:
        match = robot_topic.match(topic)
        if match and SIM_NODE in nodes and int(match.group(1)) < n:
            counts[int(match.group(1))] += 1
    return min(counts) == max(counts) >= 9


def watch_registration(n, profile, started_at, result, timeout_s=600.0):
    """Poll the master until every robot's topics are registered; store the time taken."""
    master = rosgraph.Master("/bench_registration_watch")
    robot_topic = re.compile(PROFILE_TOPICS[profile][2])
    while time.monotonic() - started_at < timeout_s:
        if robots_registered(master, n, robot_topic):
            result["topics_s"] = round(time.monotonic() - started_at, 3)
            return
        time.sleep(0.05)


def subscriber_connections(node, regex):
    """(topics of ``node`` matching ``regex`` that the subscriber holds a connection to, all
    such topics), as ``node`` itself lists them (``getBusInfo``): a connection the subscriber
    opened but the publisher never accepted does not count."""
    master = rosgraph.Master("/bench_connection_watch")
    pattern = re.compile(regex)
    publishers, _subscribers, _services = master.getSystemState()
    expected = {t for t, nodes in publishers if node in nodes and pattern.match(t)}
    _code, _msg, bus = xmlrpc.client.ServerProxy(master.lookupNode(node)).getBusInfo(
        "/bench_connection_watch")
    connected = {c[4] for c in bus if c[1].startswith("/subscribe_all") and c[4] in expected}
    return len(connected), len(expected)


def wait_connected(node, regex, timeout_s):
    """Wait until the subscriber holds every topic; the last (connected, expected) counts."""
    deadline = time.monotonic() + timeout_s
    counts = (0, 1)
    while time.monotonic() < deadline:
        try:
            counts = subscriber_connections(node, regex)
        except OSError:      # a node busy accepting thousands of connections answers late
            pass
        if counts[0] >= counts[1]:
            break
        time.sleep(0.5)
    return counts


def run_ours(n, measure_s, subscribe, cell_m, profile="vrep"):
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}")
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    world = scene_file(n, cell_m)
    sim = sub = None
    try:
        time.sleep(1.0)
        rospy.init_node("bench_driver", anonymous=True, disable_signals=True)
        clock = ClockWatch()
        registration = {}
        started_at = time.monotonic()
        watcher = threading.Thread(target=watch_registration,
                                   args=(n, profile, started_at, registration), daemon=True)
        watcher.start()
        sim = subprocess.Popen(["rosrun", "epuck_vrep_compat", "epuck_sim", f"_n:={n}",
                                f"_world:={world}", "_rtf:=0.0", "_cmd_timeout_s:=0.0",
                                "_noise:=true", f"_profile:={profile}",
                                "_cmd_vel_scaling:=si"], env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 600
        while clock.sim_s == 0.0 and time.monotonic() < deadline:
            time.sleep(0.01)
        watcher.join()
        cmd_topic, regex, _robot_topic = PROFILE_TOPICS[profile]
        pubs = [rospy.Publisher(cmd_topic.format(i=i), Twist, queue_size=1, latch=True)
                for i in range(n)]
        cmd = Twist()
        cmd.linear.x = 0.08
        for p in pubs:
            p.publish(cmd)
        if subscribe:
            sub = subprocess.Popen([os.path.join(HERE, "build", "subscribe_all"),
                                    "--regex", regex], env=env,
                                   stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        time.sleep(5.0 + n / 50.0)       # connections (latched commands, subscriber) settle
        connected = None
        if sub is not None:   # measure only once the simulator accepted every subscription
            connected = wait_connected(SIM_NODE, regex, CONNECT_TIMEOUT_S + n / 10.0)
            sub.send_signal(signal.SIGUSR1)   # the subscriber counts this window only
        rtf = clock.rtf_over(measure_s)
        result = {"sim": "epuck_vrep_compat", "profile": profile, "robots": n, "step_s": 0.05,
                  "scenario": "b_all_subscribed" if subscribe else "a_none_subscribed",
                  "rtf": round(rtf, 3), "peak_rss_mb": round(peak_rss_mb(sim.pid), 1),
                  "cell_m": cell_m, "first_step_s": round(clock.first_at - started_at, 3),
                  "topics_s": registration.get("topics_s")}
        if result["topics_s"] is not None:
            result["startup_s"] = max(result["first_step_s"], result["topics_s"])
        if connected is not None:
            result["connected_topics"], result["subscribed_topics"] = connected
        if sub is not None:
            sub.send_signal(2)
            try:
                out, _ = sub.communicate(timeout=180)   # closing 14k connections takes a while
            except subprocess.TimeoutExpired:
                sub.kill()
                out, _ = sub.communicate()
            line = out.decode().strip().splitlines()
            if line:
                stats = json.loads(line[-1])
                result["subscriber_topics"] = stats["topics"]
                result["subscriber_msgs_per_s"] = round(stats["rate_hz_total"])
        return result
    finally:
        for p in (sub, sim):
            if p is not None and p.poll() is None:
                p.terminate()
                try:
                    p.wait(timeout=60)
                except subprocess.TimeoutExpired:   # the row stands; the process goes
                    print(f"{p.args[:3]} did not end within 60 s of SIGTERM; killed",
                          file=sys.stderr, flush=True)
                    p.kill()
                    p.wait()
        rospy.signal_shutdown("benchmark done")
        master.terminate()
        master.wait(timeout=30)
        os.unlink(world)


def run_floor(n, measure_s):
    """The bare C++ sender of scenario (b)'s messages to the same subscriber (one record)."""
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}")
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    settle_s = 5.0 + n / 50.0
    sender = sub = None
    try:
        time.sleep(1.0)
        sender = subprocess.Popen([os.path.join(HERE, "build", "floor_sender"), "--robots",
                                   str(n), "--duration", str(settle_s + measure_s + 600)],
                                  env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        sub = subprocess.Popen([os.path.join(HERE, "build", "subscribe_all"),
                                "--regex", r"^/(ePuck\d+/.*|tf)$"], env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        time.sleep(settle_s)
        sub.send_signal(signal.SIGUSR1)          # count from here, everything connected
        time.sleep(measure_s)
        sub.send_signal(signal.SIGINT)
        stats = json.loads(sub.communicate(timeout=180)[0].decode().strip().splitlines()[-1])
        sender.send_signal(signal.SIGINT)
        sent = json.loads(sender.communicate(timeout=60)[0].decode().strip().splitlines()[-1])
        return {"sender": "floor_cpp", "robots": n, "subscriber_topics": stats["topics"],
                "subscriber_msgs_per_s": round(stats["rate_hz_total"]),
                "sender_steps_rtf": sent["rtf"]}
    finally:
        for p in (sub, sender, master):
            if p is not None and p.poll() is None:
                p.kill()
                p.wait(timeout=30)


def run_enki_cpp(n, step_s, sim_seconds, cell_m):
    """Enki's C++ library driven from C++ (bench/build/enki_swarm), one JSON record."""
    out = subprocess.run([os.path.join(HERE, "build", "enki_swarm"), "--robots", str(n),
                          "--step", str(step_s), "--sim-seconds", str(sim_seconds),
                          "--cell-m", str(cell_m)],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def run_pyenki(n, sim_seconds, cell_m):
    """Debian's pyenki at Enki's 10 ms step, Python Braitenberg and no controller."""
    out = subprocess.run([sys.executable, os.path.join(HERE, "enki_peer.py"), "--robots", str(n),
                          "--sim-seconds", str(sim_seconds), "--controller", "both", "--json",
                          "--cell-m", str(cell_m)],
                         capture_output=True, text=True, check=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def run_peers(n, cell_m):
    """Enki C++ at 10 ms and 50 ms, then pyenki; each long enough for several wall seconds."""
    rows = [run_enki_cpp(n, step_s, 5.0 if n >= 1000 else 20.0, cell_m)
            for step_s in (0.01, 0.05)]
    return rows + run_pyenki(n, 2.0 if n >= 1000 else 20.0, cell_m)


def machine():
    return {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count(),
            "python": platform.python_version(), "kernel": platform.release()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robots", type=int, nargs="+", default=[1, 10, 100, 1000])
    ap.add_argument("--measure-s", type=float, default=10.0)
    ap.add_argument("--cell-m", type=float, default=CELL_SIDE_M,
                    help="side of each robot's square start cell (m), for every simulator")
    ap.add_argument("--floor", action="store_true",
                    help="also measure (b)'s per-message floor with a bare C++ sender")
    ap.add_argument("--epuck2-robots", type=int, nargs="*", default=[100],
                    help="N of the epuck2_driver rows (none: skip them)")
    ap.add_argument("--no-enki", action="store_true", help="skip the Enki peers")
    ap.add_argument("--peers-only", action="store_true",
                    help="run only Enki C++ and pyenki (to check the peers quickly)")
    ap.add_argument("--json", help="append JSON lines here")
    args = ap.parse_args()
    rows = [{"machine": machine()}]
    for n in args.robots:
        if not args.peers_only:
            rows += run_scenarios(n, args.measure_s, args.cell_m, "vrep")
        if args.floor and not args.peers_only:
            rows.append(run_floor(n, args.measure_s))
            print(json.dumps(rows[-1]), flush=True)
        if args.no_enki:
            continue
        for r in run_peers(n, args.cell_m):
            rows.append(r)
            print(json.dumps(r), flush=True)
    for n in [] if args.peers_only else args.epuck2_robots:
        rows += run_scenarios(n, args.measure_s, args.cell_m, "epuck2_driver")
    print(markdown_table(rows), flush=True)
    if args.json:
        with open(args.json, "a") as f:
            for r in rows:
                f.write(json.dumps(r) + "\n")


def run_scenarios(n, measure_s, cell_m, profile):
    """Scenarios (a) and (b) at N robots, each in its own process (rospy allows one
    init_node per process)."""
    rows = []
    for subscribe in (False, True):
        out = subprocess.run([sys.executable, __file__, "--one", str(n), str(int(subscribe)),
                              str(measure_s), str(cell_m), profile],
                             capture_output=True, text=True)
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]) if out.returncode == 0
                    else {"robots": n, "profile": profile, "error": out.stderr[-500:]})
        print(json.dumps(rows[-1]), flush=True)
    return rows


if __name__ == "__main__":
    if len(sys.argv) == 7 and sys.argv[1] == "--one":
        print(json.dumps(run_ours(int(sys.argv[2]), float(sys.argv[4]), bool(int(sys.argv[3])),
                                  float(sys.argv[5]), sys.argv[6])))
    else:
        main()

#!/usr/bin/python3
"""Real-time factor and peak memory of epuck_vrep_compat against Enki, in one run.

For each N: a square walled arena sized like Enki's (0.15 m per robot on a grid), N e-pucks,
noise on, every topic advertised, ``rtf:=0`` (as fast as possible), 50 ms step (V-REP's
default; Enki runs its 10 ms step: the real-time factor compares simulated seconds per wall
second, whatever the step). Every robot gets one constant forward ``cmd_vel`` (watchdog off)
and drives into walls and neighbours, so collisions and IR cones are exercised.

Scenarios: (a) nobody subscribed; (b) one separate C++ process (``subscribe_all``) takes every
topic of every robot and ``/tf``. Memory is the simulator process's peak RSS (VmHWM).
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
import socket
import subprocess
import sys
import tempfile
import time

import rospy
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock

HERE = os.path.dirname(os.path.abspath(__file__))
CELL_SIDE_M = 0.15
ARENA_MARGIN_M = 0.10


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def scene_file(n):
    side = CELL_SIDE_M * math.ceil(math.sqrt(n)) + ARENA_MARGIN_M
    f = tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False)
    f.write(f"arena:\n  size_m: [{side}, {side}]\n")
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
        rospy.Subscriber("/clock", Clock, self._cb, queue_size=1)

    def _cb(self, msg):
        self.sim_s = msg.clock.to_sec()

    def rtf_over(self, wall_s):
        s0, t0 = self.sim_s, time.monotonic()
        time.sleep(wall_s)
        return (self.sim_s - s0) / (time.monotonic() - t0)


PROFILE_TOPICS = {"vrep": ("/ePuck{i}/cmd_vel", r"^/(ePuck\d+/.*|tf)$"),
                  "epuck2_driver": ("/epuck_robot_{i}/mobile_base/cmd_vel",
                                    r"^/(epuck_robot_\d+/.*|tf)$")}


def run_ours(n, measure_s, subscribe, profile="vrep"):
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}")
    os.environ["ROS_MASTER_URI"] = env["ROS_MASTER_URI"]
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    world = scene_file(n)
    sim = sub = None
    try:
        time.sleep(1.0)
        sim = subprocess.Popen(["rosrun", "epuck_vrep_compat", "epuck_sim", f"_n:={n}",
                                f"_world:={world}", "_rtf:=0.0", "_cmd_timeout_s:=0.0",
                                "_noise:=true", f"_profile:={profile}",
                                "_cmd_vel_scaling:=si"], env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
        rospy.init_node("bench_driver", anonymous=True, disable_signals=True)
        clock = ClockWatch()
        deadline = time.monotonic() + 600
        while clock.sim_s == 0.0 and time.monotonic() < deadline:
            time.sleep(0.1)
        cmd_topic, regex = PROFILE_TOPICS[profile]
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
        rtf = clock.rtf_over(measure_s)
        result = {"sim": "epuck_vrep_compat", "profile": profile, "robots": n, "step_s": 0.05,
                  "scenario": "b_all_subscribed" if subscribe else "a_none_subscribed",
                  "rtf": round(rtf, 3), "peak_rss_mb": round(peak_rss_mb(sim.pid), 1)}
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
                p.wait(timeout=30)
        rospy.signal_shutdown("benchmark done")
        master.terminate()
        master.wait(timeout=30)
        os.unlink(world)


def run_enki(n, sim_seconds):
    out = subprocess.run([sys.executable, os.path.join(HERE, "enki_peer.py"), "--robots", str(n),
                          "--sim-seconds", str(sim_seconds), "--controller", "both", "--json"],
                         capture_output=True, text=True, check=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def machine():
    return {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count(),
            "python": platform.python_version(), "kernel": platform.release()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robots", type=int, nargs="+", default=[1, 10, 100, 1000])
    ap.add_argument("--measure-s", type=float, default=10.0)
    ap.add_argument("--epuck2-robots", type=int, nargs="*", default=[100],
                    help="N of the epuck2_driver rows (none: skip them)")
    ap.add_argument("--no-enki", action="store_true", help="skip the Enki peer")
    ap.add_argument("--json", help="append JSON lines here")
    args = ap.parse_args()
    rows = [{"machine": machine()}]
    for n in args.robots:
        rows += run_scenarios(n, args.measure_s, "vrep")
        if args.no_enki:
            continue
        enki_seconds = 2.0 if n >= 1000 else 20.0
        for r in run_enki(n, enki_seconds):
            rows.append(r)
            print(json.dumps(r), flush=True)
    for n in args.epuck2_robots:
        rows += run_scenarios(n, args.measure_s, "epuck2_driver")
    if args.json:
        with open(args.json, "a") as f:
            for r in rows:
                f.write(json.dumps(r) + "\n")


def run_scenarios(n, measure_s, profile):
    """Scenarios (a) and (b) at N robots, each in its own process (rospy allows one
    init_node per process)."""
    rows = []
    for subscribe in (False, True):
        out = subprocess.run([sys.executable, __file__, "--one", str(n), str(int(subscribe)),
                              str(measure_s), profile], capture_output=True, text=True)
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]) if out.returncode == 0
                    else {"robots": n, "profile": profile, "error": out.stderr[-500:]})
        print(json.dumps(rows[-1]), flush=True)
    return rows


if __name__ == "__main__":
    if len(sys.argv) == 6 and sys.argv[1] == "--one":
        print(json.dumps(run_ours(int(sys.argv[2]), float(sys.argv[4]), bool(int(sys.argv[3])),
                                  sys.argv[5])))
    else:
        main()

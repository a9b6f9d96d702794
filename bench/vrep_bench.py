#!/usr/bin/python3
"""The /vrep face's speed: service round trip against a bare rospy service, and the step rate
with 50 enabled streams, measured in one run.

1. A persistent proxy to ``/vrep/simRosGetObjectHandle`` against a persistent proxy to a bare
   rospy service of the same shape (string in, int32 out) in a separate process: mean round
   trip over ``--calls`` calls each, and their ratio.
2. The simulator at ``rtf`` 1 with 50 publisher streams enabled through
   ``/vrep/simRosEnablePublisher`` (joint states, object poses, proximity sensors, vision
   sensor info) and a C++ process subscribed to all of them: the rate of ``/vrep/info`` in
   simulated time (V-REP's 50 ms step: 20 Hz) and in wall time.
Needs a built workspace, sourced, and ``bench/build.sh`` run.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

from run_benchmark import free_port     # bench/: one free port finder

import rospy

HERE = os.path.dirname(os.path.abspath(__file__))
BARE_SERVER = """
import rospy
from vrep_common.srv import simRosGetObjectHandle, simRosGetObjectHandleResponse
rospy.init_node("bare_service")
rospy.Service("/bare/simRosGetObjectHandle", simRosGetObjectHandle,
              lambda req: simRosGetObjectHandleResponse(42))
rospy.spin()
"""


def mean_round_trip_us(name, calls):
    from vrep_common.srv import simRosGetObjectHandle
    rospy.wait_for_service(name, timeout=60)
    proxy = rospy.ServiceProxy(name, simRosGetObjectHandle, persistent=True)
    for _ in range(100):
        proxy("ePuck_leftJoint")
    start = time.perf_counter()
    for _ in range(calls):
        proxy("ePuck_leftJoint")
    return 1e6 * (time.perf_counter() - start) / calls


def enable_streams(count):
    from vrep_common.srv import simRosEnablePublisher, simRosGetObjects
    enable = rospy.ServiceProxy("/vrep/simRosEnablePublisher", simRosEnablePublisher)
    objects = rospy.ServiceProxy("/vrep/simRosGetObjects", simRosGetObjects)
    joints = objects(1).handles
    prox = objects(5).handles
    every = objects(-2).handles
    plan = ([(4102, h, 0) for h in joints] + [(4112, h, 0) for h in prox]
            + [(8193, h, -1) for h in every])
    topics = []
    for cmd, aux1, aux2 in plan[:count]:
        topics.append(enable(f"s{len(topics)}", 1, cmd, aux1, aux2, "").effectiveTopicName)
    return [t for t in topics if t]


def info_rates(seconds):
    from vrep_common.msg import VrepInfo
    stamps = []
    sub = rospy.Subscriber("/vrep/info", VrepInfo,
                           lambda m: stamps.append((time.monotonic(), m.simulationTime.data)),
                           queue_size=100)
    time.sleep(seconds)
    sub.unregister()
    (w0, s0), (w1, s1) = stamps[0], stamps[-1]
    return (len(stamps) - 1) / max(s1 - s0, 1e-9), (len(stamps) - 1) / (w1 - w0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--calls", type=int, default=3000)
    ap.add_argument("--robots", type=int, default=2)
    ap.add_argument("--streams", type=int, default=50)
    args = ap.parse_args()
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}")
    os.environ.update(env)
    procs = [subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        time.sleep(1.0)
        procs.append(subprocess.Popen(["rosrun", "epuck_vrep_compat", "epuck_sim",
                                       f"_n:={args.robots}", "_rtf:=1.0"], env=env,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as f:
            f.write(BARE_SERVER)
        procs.append(subprocess.Popen([sys.executable, f.name], env=env,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        rospy.init_node("vrep_bench", disable_signals=True)
        vrep_us = mean_round_trip_us("/vrep/simRosGetObjectHandle", args.calls)
        bare_us = mean_round_trip_us("/bare/simRosGetObjectHandle", args.calls)
        print(json.dumps({"service_round_trip_us": round(vrep_us, 1),
                          "bare_rospy_round_trip_us": round(bare_us, 1),
                          "ratio": round(vrep_us / bare_us, 2)}), flush=True)
        topics = enable_streams(args.streams)
        procs.append(subprocess.Popen([os.path.join(HERE, "build", "subscribe_all"),
                                       "--regex", r"^/vrep/s\d+$"], env=env,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        time.sleep(3.0)
        sim_hz, wall_hz = info_rates(10.0)
        print(json.dumps({"streams_enabled": len(topics), "info_hz_sim_time": round(sim_hz, 2),
                          "info_hz_wall": round(wall_hz, 2)}), flush=True)
    finally:
        rospy.signal_shutdown("done")
        for p in reversed(procs):
            p.terminate()
            p.wait(timeout=30)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""The full MERLIN cell with every thesis node running and every topic subscribed.

Starts a private master, ``roslaunch epuck_vrep_compat merlin_cell.launch`` (all nodes) and a C++
process subscribed to every topic (``bench/build/subscribe_all --per-topic``), then measures
over ``--seconds`` of wall time:
- the real-time factor, twice: with the simulator holding real time (``rtf:=1``, the default
  use: the factor must be 1.0) and flat out (``rtf:=0``: how much faster than real time the
  cell can go, target 2.0);
- each topic's rate in simulated time (messages / simulated seconds) and in wall time (the thesis
  nodes poll ``/vrep`` on a wall-clock rate, so flat out they fall behind in simulated time);
- the simulator's peak resident memory (VmHWM).
With ``--safety`` the cell is ``merlin_safety.launch`` with the thesis's nodes, every robot
supervised and the operator tracked (operator_tracker, ssm_supervisor, the kinect node), and each
run also reports the supervisor's reaction: per approach of the operator, the simulated steps
from the IRB 140's published separation first falling below its S_p to the published scale
first below 1 (negative: the slowdown began before S_p was crossed, as it is meant to).
Needs a built, sourced workspace and ``bench/build.sh``. Prints one JSON line per run and a
table; ``--json FILE`` writes both runs.
"""
import argparse
import json
import os
import platform
import signal
import subprocess
import sys
import time

import rosgraph
import rospy
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Float64

from run_benchmark import end_group, free_port

HERE = os.path.dirname(os.path.abspath(__file__))


def peak_rss_mb(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return float("nan")


def simulator_pid(master_uri):
    """The pid of the /vrep node, from its XML-RPC API."""
    import xmlrpc.client
    master = rosgraph.Master("/cell_bench", master_uri=master_uri)
    uri = master.lookupNode("/vrep")
    return xmlrpc.client.ServerProxy(uri).getPid("/cell_bench")[2]


class ReactionMeter:
    """The supervisor's reaction per approach (see the module's docstring), in steps."""

    def __init__(self, clock, step_s=0.05, robot="IRB140"):
        self.clock, self.step_s = clock, step_s
        self.latest = {}
        self.crossed_at = self.slowed_at = None
        self.measured = False           # this approach's reaction is in
        self.reactions = []
        ns = f"/ssm_supervisor/{robot}/"
        self._subs = [rospy.Subscriber(ns + k, Float64, self._on, k, queue_size=10)
                      for k in ("separation", "protective_separation", "scale")]

    def _on(self, msg, key):
        self.latest[key] = msg.data
        if len(self.latest) < 3:
            return
        t = self.clock["t"]
        inside = self.latest["separation"] < self.latest["protective_separation"]
        slowed = self.latest["scale"] < 1.0
        if self.slowed_at is None and slowed:
            self.slowed_at = t
        if self.crossed_at is None and inside:
            self.crossed_at = t
        if not self.measured and self.crossed_at is not None and self.slowed_at is not None:
            self.reactions.append(round((self.slowed_at - self.crossed_at) / self.step_s))
            self.measured = True
        if not slowed and not inside:              # the operator has left: a new approach
            self.crossed_at = self.slowed_at = None
            self.measured = False


def run(rtf, seconds, safety=False):
    port = free_port()
    uri = f"http://127.0.0.1:{port}"
    env = dict(os.environ, ROS_MASTER_URI=uri)
    os.environ["ROS_MASTER_URI"] = uri
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    launch = sub = None
    try:
        time.sleep(1.0)
        command = (["merlin_safety.launch", "nodes:=true", "robots:=[]"] if safety
                   else ["merlin_cell.launch"])
        launch = subprocess.Popen(["roslaunch", "epuck_vrep_compat", *command,
                                   f"rtf:={rtf}"], env=env, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL, start_new_session=True)
        rospy.init_node("cell_bench", anonymous=True, disable_signals=True)
        clock = {"t": 0.0}
        rospy.Subscriber("/clock", Clock, lambda m: clock.__setitem__("t", m.clock.to_sec()),
                         queue_size=1)
        deadline = time.monotonic() + 120
        while clock["t"] < 2.0 and time.monotonic() < deadline:
            time.sleep(0.1)
        time.sleep(5.0)                 # every node up and publishing
        meter = ReactionMeter(clock) if safety else None
        sub = subprocess.Popen([os.path.join(HERE, "build", "subscribe_all"), "--per-topic",
                                "--regex", r"^/(?!rosout).*"], env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        time.sleep(3.0)                 # subscriptions connected
        sub.send_signal(signal.SIGUSR1)  # count from here
        s0, w0 = clock["t"], time.monotonic()
        time.sleep(seconds)
        s1, w1 = clock["t"], time.monotonic()
        sub.send_signal(signal.SIGINT)
        out, _ = sub.communicate(timeout=60)
        stats = json.loads(out.decode().strip().splitlines()[-1])
        sim_s, wall_s = s1 - s0, w1 - w0
        per_topic = sorted(stats["per_topic"].items())
        rates = {t: round(v["messages"] / sim_s, 2) for t, v in per_topic}
        wall_rates = {t: round(v["messages"] / wall_s, 2) for t, v in per_topic}
        return {"rtf_requested": rtf, "rtf": round(sim_s / (w1 - w0), 3),
                "topics": stats["topics"], "messages_per_wall_s": round(stats["rate_hz_total"]),
                "mbytes_per_wall_s": round(stats["bytes"] / stats["wall_s"] / 1e6, 2),
                "peak_rss_mb": round(peak_rss_mb(simulator_pid(uri)), 1),
                "rate_per_sim_s": rates, "rate_per_wall_s": wall_rates,
                "reaction_steps": meter.reactions if meter is not None else None}
    finally:
        if sub is not None and sub.poll() is None:
            sub.kill()
        end_group(launch, 30.0)
        rospy.signal_shutdown("benchmark done")
        master.terminate()
        master.wait(timeout=30)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=30.0, help="wall time measured per run")
    ap.add_argument("--json", help="write the results here")
    ap.add_argument("--safety", action="store_true",
                    help="merlin_safety.launch: tracker and supervisor too")
    ap.add_argument("--one", type=float, help=argparse.SUPPRESS)   # one run, in a child
    args = ap.parse_args()
    if args.one is not None:
        print(json.dumps(run(args.one, args.seconds, args.safety)), flush=True)
        return
    machine = {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count(),
               "python": platform.python_version(), "kernel": platform.release()}
    with open("/proc/cpuinfo") as f:
        models = [line.split(":", 1)[1].strip() for line in f if line.startswith("model name")]
    machine["cpu_model"] = models[0] if models else ""
    results = []
    for rtf in (1.0, 0.0):
        # a process per run: rospy's node cannot move to another master
        out = subprocess.run([sys.executable, __file__, "--one", str(rtf), "--seconds",
                              str(args.seconds)] + (["--safety"] if args.safety else []),
                             capture_output=True, text=True, check=True)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(json.dumps(r), flush=True)
        results.append(r)
    print(f"machine: {machine}")
    print("messages per simulated second / per wall second")
    print(f"{'topic':32s} " + " ".join(f"{'rtf:=' + str(r['rtf_requested']):>17s}"
                                       for r in results))
    topics = sorted(set().union(*(r["rate_per_sim_s"] for r in results)))
    for t in topics:
        print(f"{t:32s} " + " ".join(f"{r['rate_per_sim_s'].get(t, 0.0):>8.2f}/"
                                     f"{r['rate_per_wall_s'].get(t, 0.0):<8.2f}"
                                     for r in results))
    for r in results:
        print(f"rtf:={r['rtf_requested']}: achieved RTF {r['rtf']}, peak RSS "
              f"{r['peak_rss_mb']} MB, {r['topics']} topics"
              + (f", supervisor reaction {r['reaction_steps']} steps" if args.safety else ""))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"machine": machine, "runs": results}, f, indent=1)


if __name__ == "__main__":
    main()

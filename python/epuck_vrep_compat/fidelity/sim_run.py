"""Runs a section 4.1 scenario in the simulator and records it: the half of ``sim_vs_real``
that talks to ROS.

The simulator is started as its own ``roslaunch`` (``epucks.launch``, the scenario's world,
profile ``vrep``), so this client loads nothing of it. Commands are the bag's ``cmd_vel`` replayed
at their times (seconds from the bag's start, compared with the simulator's ``/clock``), else the
scenario's drive. Every IR and IMU message of ``/ePuck0`` is written to a bag until the
simulated time reaches the duration; progress goes to stderr once per simulated second.
"""
import os
import signal
import subprocess
import sys
import threading
import time

import rosbag
import rosgraph
import rospy
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, Range
from std_srvs.srv import Empty

from epuck_vrep_compat.compat.epuck_names import PROXIMITY_COUNT, VREP
from epuck_vrep_compat.compat.topics import CLOCK_TOPIC, UNPAUSE_SERVICE

ROBOT = VREP.robot_name(0)
START_TIMEOUT_S = 120.0       # wall time for a simulator to publish its first /clock


class SimulatorRun:
    """One simulated run, recorded into ``bag_path`` (roslaunch's output beside it,
    ``<label>.launch.log``)."""

    def __init__(self, label, world, launch_args, bag_path):
        self.label, self.world, self.launch_args, self.bag_path = (label, world, launch_args,
                                                                   bag_path)
        self._lock = threading.Lock()
        self._clock = -1.0
        self._bag = None

    def run(self, duration_s, commands, seed=0, rtf=1.0):
        """Launch, replay ``commands`` ((t, speed) sorted, or a callable t -> speed), record
        ``duration_s`` of simulated time, shut the simulator down."""
        args = ["roslaunch", "epuck_vrep_compat", "epucks.launch", f"world:={self.world}",
                f"seed:={seed}", f"rtf:={rtf}", "n:=1", "paused:=true"] + self.launch_args
        log_path = os.path.splitext(self.bag_path)[0] + ".launch.log"
        with open(log_path, "wb") as log:     # the child keeps its own descriptor
            proc = subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT,
                                    start_new_session=True)
        proc.log_path = log_path
        self._bag = rosbag.Bag(self.bag_path, "w")
        subs = [rospy.Subscriber(CLOCK_TOPIC, Clock, self._on_clock, queue_size=100)]
        roles = [(f"proximity{k}", Range) for k in range(PROXIMITY_COUNT)] + [("imu", Imu)]
        for role, kind in roles:
            topic = VREP.topic(ROBOT, role)
            subs.append(rospy.Subscriber(topic, kind, self._write, topic, queue_size=1000))
        pub = rospy.Publisher(VREP.topic(ROBOT, "cmd_vel"), Twist, queue_size=10)
        try:
            self._wait_start(proc, subs, pub)
            self._drive(pub, duration_s, commands)
        finally:
            for s in subs:
                s.unregister()
            pub.unregister()
            _stop(proc)
            with self._lock:
                self._bag.close()

    def _on_clock(self, msg):
        with self._lock:
            self._clock = msg.clock.to_sec()

    def _write(self, msg, topic):
        with self._lock:
            if 0.0 < self._clock and self._bag is not None:
                self._bag.write(topic, msg, msg.header.stamp)

    def now(self):
        with self._lock:
            return self._clock

    def _wait_start(self, proc, subs, pub):
        """Waits for the simulator (started paused) to connect to every subscriber, unpauses
        it, and waits for its first /clock: nothing of the run is missed."""
        deadline = time.monotonic() + START_TIMEOUT_S
        while any(s.get_num_connections() == 0 for s in subs[1:] + [pub]):
            self._check_alive(proc, deadline)
            time.sleep(0.01)
        rospy.wait_for_service(UNPAUSE_SERVICE, timeout=START_TIMEOUT_S)
        rospy.ServiceProxy(UNPAUSE_SERVICE, Empty)()
        while self.now() <= 0.0:
            self._check_alive(proc, deadline)
            time.sleep(0.01)

    @staticmethod
    def _check_alive(proc, deadline):
        if proc.poll() is not None:
            with open(proc.log_path, "rb") as log:
                tail = log.read().decode(errors="replace")[-2000:]
            raise RuntimeError(f"the simulator ended with status {proc.returncode}: {tail}")
        if time.monotonic() > deadline:
            raise RuntimeError(f"the simulator did not start in {START_TIMEOUT_S} s")

    def _drive(self, pub, duration_s, commands):
        shown, sent, cmd = -1, 0, Twist()
        while self.now() < duration_s:
            t = self.now()
            if callable(commands):
                cmd.linear.x = commands(t)
            else:
                while sent < len(commands) and commands[sent][0] <= t:
                    cmd.linear.x = commands[sent][1]
                    sent += 1
            pub.publish(cmd)
            if int(t) != shown:
                shown = int(t)
                print(f"sim_vs_real: {self.label}: {t:5.1f} / {duration_s:.1f} s simulated",
                      file=sys.stderr, flush=True)
            time.sleep(0.01)


def _stop(proc):
    """Ends the roslaunch this module started (its process group), politely first."""
    if proc.poll() is None:
        for sig, wait_s in ((signal.SIGINT, 30.0), (signal.SIGTERM, 10.0), (signal.SIGKILL, 5.0)):
            os.killpg(proc.pid, sig)
            try:
                proc.wait(wait_s)
                return
            except subprocess.TimeoutExpired:
                continue


def ensure_master():
    """A master to talk to: the running one, or a ``rosmaster`` started here (returned, to be
    stopped by the caller; None when one was running)."""
    if rosgraph.is_master_online():
        return None
    port = rosgraph.get_master_uri().rsplit(":", 1)[-1].strip("/")
    proc = subprocess.Popen(["rosmaster", "--core", "-p", port], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + 30.0
    while not rosgraph.is_master_online():
        if time.monotonic() > deadline or proc.poll() is not None:
            raise RuntimeError("could not start a ROS master")
        time.sleep(0.1)
    return proc


def stop_master(proc):
    if proc is not None:
        _stop(proc)

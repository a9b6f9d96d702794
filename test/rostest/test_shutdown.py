#!/usr/bin/python3
"""A simulator of 100 e-pucks, every topic subscribed and a bag recording, stopped by SIGINT.

rospy's own way out took seconds to tens of seconds at this load (per-topic master calls, a
TCPROS server still accepting, a ``TypeError`` from a closed topic), and roslaunch escalates to
SIGTERM and SIGKILL, cutting a recorder's end. The simulator now stops itself
(``ros/node/stop.py``). What is checked is what others can see: the process ends by itself
with status 0 and no traceback, the master holds none of its registrations, the simulator
closed every subscriber's connection, and a ``rosbag record`` of ``/clock`` and one sensor
running through the stop is readable and ends at the last step. How long a stop takes is a
benchmark (``bench/shutdown.py``), not a test: the waits below are liveness guards only.
"""
import os
import re
import resource
import signal
import subprocess
import tempfile
import time
import unittest
import xmlrpc.client

import rosbag
import rosgraph
import rospy
import rostest
from rosgraph_msgs.msg import Clock

from raw_tcpros import RawSubscriber, pump, subscribe_all, tcpros_address
from sim_test_helpers import PKG, master_knows, simulator_topics, wait_for_message
from repo import REPO  # test/ on the path: sim_test_helpers  # isort: skip

N = 100
STEP_S = 0.05
SENSOR = "/ePuck0/proximity0"
WORLD = os.path.join(REPO, "test", "worlds", "swarm.yaml")
LIVENESS_S = 300.0    # a guard against a hang, far beyond what a stop takes
STOPPED = re.compile(r"epuck_sim stops \(SIGINT at t=([0-9.]+) s\)")


def bus_callers(node_uri):
    """The caller ids of every connection of the node, per topic."""
    _code, _msg, bus = xmlrpc.client.ServerProxy(node_uri).getBusInfo("/test_shutdown")
    callers = {}
    for connection in bus:
        callers.setdefault(connection[4], set()).add(connection[1])
    return callers


def _wait_group_gone(pgid):
    """Until no process of the group is left (liveness)."""
    deadline = time.monotonic() + LIVENESS_S
    while time.monotonic() < deadline:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return
        time.sleep(0.05)


def _held(master):
    """The topics and services the master lists /vrep for."""
    return [name for kind in master.getSystemState() for name, nodes in kind if "/vrep" in nodes]


class Shutdown(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
        resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))   # 1400 connections here
        rospy.init_node("test_shutdown", disable_signals=True)
        cls.tmp = tempfile.mkdtemp(prefix="test_shutdown_")
        cls.log_path = os.path.join(cls.tmp, "simulator.log")
        cls.bag_path = os.path.join(cls.tmp, "stop.bag")
        with open(cls.log_path, "w") as log:
            cls.sim = subprocess.Popen(
                ["rosrun", PKG, "epuck_sim", f"_n:={N}", f"_world:={WORLD}", f"_step_s:={STEP_S}"],
                stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
                env=dict(os.environ, PYTHONFAULTHANDLER="1"))
        wait_for_message("/clock", Clock, timeout_s=LIVENESS_S)
        cls.sim_uri = rosgraph.Master("/test_shutdown").lookupNode("/vrep")
        published, _subscribed, _types = simulator_topics()
        cls.topics = sorted(published - {"/rosout"})
        cls.record = subprocess.Popen(["rosbag", "record", "-O", cls.bag_path, "/clock", SENSOR],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                      start_new_session=True)
        cls.subs = subscribe_all(cls.topics, tcpros_address(cls.sim_uri, cls.topics[0]),
                                 LIVENESS_S)
        cls.connected = cls._wait_connected()
        # two simulated seconds recorded and read by everyone, then the stop; the subscriber
        # reads everything up to and through it
        clock = cls.subs["/clock"]
        until = clock.messages + round(2.0 / STEP_S)
        pump(cls.subs, lambda: clock.messages >= until, LIVENESS_S)
        os.kill(cls.sim.pid, signal.SIGINT)
        pump(cls.subs, lambda: cls.sim.poll() is not None, LIVENESS_S)
        if cls.sim.poll() is None:                 # hung: its threads' stacks into the log
            os.kill(cls.sim.pid, signal.SIGABRT)
        cls.sim.wait()
        pump(cls.subs, lambda: all(s.closed for s in cls.subs.values()), LIVENESS_S)
        cls.record.send_signal(signal.SIGINT)     # rosbag's script passes it on and exits;
        cls.record.wait()
        _wait_group_gone(cls.record.pid)          # its recorder closes the bag, then ends
        with open(cls.log_path) as log:
            cls.output = log.read()

    @classmethod
    def _wait_connected(cls):
        """Until every raw subscription and the recorder's two are connected at the simulator
        (liveness); whether they all were."""
        deadline = time.monotonic() + LIVENESS_S
        while time.monotonic() < deadline:
            callers = bus_callers(cls.sim_uri)
            raw = all(RawSubscriber.CALLER_ID in callers.get(t, ()) for t in cls.topics)
            bag = all(any(c.startswith("/record") for c in callers.get(t, ()))
                      for t in ("/clock", SENSOR))
            if raw and bag:
                return True
            pump(cls.subs, lambda: False, 0.5)     # keep reading: nothing backs up
        return False

    @classmethod
    def tearDownClass(cls):
        for sub in cls.subs.values():
            sub.sock.close()
        for process in (cls.sim, cls.record):      # only if a test above failed midway
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()

    def test_1_everything_was_subscribed_when_it_stopped(self):
        self.assertGreater(len(self.topics), N * 13)
        self.assertTrue(self.connected, "not every subscription reached the simulator")

    def test_2_it_exits_by_itself_with_status_0_and_no_traceback(self):
        # only this test's SIGINT reached it (no SIGTERM, no SIGKILL): status 0 is its own
        self.assertEqual(self.sim.returncode, 0, self.output[-5000:])
        self.assertNotIn("Traceback", self.output)
        self.assertNotIn("TypeError", self.output)
        self.assertRegex(self.output, STOPPED)

    def test_3_the_master_holds_none_of_its_registrations(self):
        # the simulator hands them to a process of its own, which the master answers within
        # seconds of the simulator's exit: wait for it (liveness), then nothing may be left
        master = rosgraph.Master("/test_shutdown")
        deadline = time.monotonic() + LIVENESS_S
        while time.monotonic() < deadline and (_held(master) or master_knows(master)):
            time.sleep(0.1)
        self.assertEqual(_held(master), [])
        self.assertFalse(master_knows(master), "the master still knows /vrep")

    def test_4_every_subscriber_connection_ended(self):
        open_ = [t for t, s in self.subs.items() if not s.closed]
        self.assertEqual(open_, [], f"{len(open_)} connections still open")

    def test_5_the_bag_is_readable_and_ends_at_the_last_step(self):
        stop_s = float(STOPPED.search(self.output).group(1))
        clocks, stamps = [], []
        with rosbag.Bag(self.bag_path) as bag:            # closed cleanly: readable, indexed
            for topic, msg, _t in bag.read_messages(topics=["/clock", SENSOR]):
                if topic == "/clock":
                    clocks.append(msg.clock.to_sec())
                else:
                    stamps.append(msg.header.stamp.to_sec())
        self.assertGreater(len(clocks), 10)
        self.assertGreater(len(stamps), 10)
        for name, last in (("/clock", clocks[-1]), (SENSOR, stamps[-1])):
            self.assertLessEqual(last, stop_s + 1e-6, name)
            self.assertGreaterEqual(last, stop_s - STEP_S - 1e-6,
                                    f"{name} ends at {last:.3f} s, the stop was at {stop_s:.3f} s")


if __name__ == "__main__":
    rostest.rosrun(PKG, "shutdown", Shutdown)

#!/usr/bin/python3
"""Faults survived, on the swarm reference load (10 e-pucks, a 160x120 camera at 10 Hz):
a slow subscriber and a stopped one cost the others nothing and the simulator no memory; a
client killed with SIGKILL and restarted finds the simulator as it was, latched state included;
a simulator killed with SIGKILL is respawned and the subscribers already there get data again;
and a simulator whose master restarts or dies exits with status 3 instead of living on as a
zombie (checked on a master and simulator of its own)."""
import os
import signal
import socket
import subprocess
import sys
import threading
import time
import unittest
import xmlrpc.client

import rosgraph
import rospy
import rostest
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Image, Range
from std_msgs.msg import UInt8MultiArray

from epuck_vrep_compat.compat.topics import NODE
from epuck_vrep_compat.experiment.isolation import free_port
from sim_test_helpers import Collector, RosoutGuard, sim_time_now, wait_for_message

HERE = os.path.dirname(os.path.abspath(__file__))
CLIENT = os.path.join(HERE, "fault_client.py")
NOMINAL_HZ = 20.0                 # proximity topics: one message per 50 ms step
MIN_ADVANCE_S = 2.0               # simulated time the clock must advance in the 60 s window


def simulator_pid(master_uri=None):
    master = rosgraph.Master(rospy.get_name(), master_uri=master_uri)
    return xmlrpc.client.ServerProxy(master.lookupNode("/vrep")).getPid(rospy.get_name())[2]


def simulator_rss_mb():
    with open(f"/proc/{simulator_pid()}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise AssertionError("no VmRSS for the simulator")


def start_client(*args):
    return subprocess.Popen([sys.executable, CLIENT, *args], stdout=subprocess.PIPE, text=True)


def wait_line(process, prefix, timeout_s=30.0):
    """The first line of the process's output that starts with prefix."""
    found = []

    def read():
        for line in process.stdout:
            if line.startswith(prefix):
                found.append(line.strip())
                return
    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    reader.join(timeout_s)
    if not found:
        raise AssertionError(f"{CLIENT} printed no '{prefix}' line in {timeout_s} s")
    return found[0]


class Faults(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_faults")
        cls.guard = RosoutGuard()
        wait_for_message("/clock", Clock)
        wait_for_message("/ePuck0/camera", Image)

    def _rate_per_sim_s(self, collector, seconds):
        """Messages per simulated second, counted by their stamps over the simulated time that
        ``seconds`` of wall time brought (however little a loaded machine gives), and that
        simulated time."""
        s0 = sim_time_now()
        time.sleep(seconds)
        s1 = sim_time_now()
        # every message of the window has come once one stamped after it has
        collector.wait_for(lambda m: m.header.stamp.to_sec() > s1, timeout_s=60.0,
                           what=f"a message stamped after {s1:.3f} s")
        stamps = {m.header.stamp.to_sec() for m in list(collector.messages)}
        return sum(s0 < t <= s1 for t in stamps) / (s1 - s0), s1 - s0

    def test_a_slow_and_a_stopped_subscriber_cost_the_others_nothing(self):
        others = Collector("/ePuck9/proximity0", Range)
        base_rate, _ = self._rate_per_sim_s(others, 10.0)
        self.assertAlmostEqual(base_rate, NOMINAL_HZ, delta=0.1 * NOMINAL_HZ)
        # a subscriber that sleeps 1 s per camera image, and one that stops reading altogether
        slow = rospy.Subscriber("/ePuck0/camera", Image, lambda m: time.sleep(1.0))
        stuck = start_client("--mode", "reader")
        try:
            wait_line(stuck, "CONNECTED")
            time.sleep(2.0)                    # its subscriptions are connected
            stuck.send_signal(signal.SIGSTOP)
            rss0 = simulator_rss_mb()
            rate, advanced_s = self._rate_per_sim_s(others, 60.0)
            growth = simulator_rss_mb() - rss0
        finally:
            slow.unregister()
            stuck.send_signal(signal.SIGCONT)
            stuck.kill()
            stuck.wait()
        self.assertAlmostEqual(rate, NOMINAL_HZ, delta=0.1 * NOMINAL_HZ)
        # not stalled: the clock went on (a blocked write would stop it for good)
        self.assertGreater(advanced_s, MIN_ADVANCE_S)
        self.assertLess(growth, 50.0, f"simulator memory grew {growth:.1f} MB in 60 s")

    def test_b0_a_client_stalled_in_its_handshake_blocks_no_other(self):
        """A client that opens a TCPROS connection to the simulator and sends nothing (a stopped
        or starved subscriber): a new subscriber still connects and gets data. rospy reads a
        handshake in its accept thread with no time-out; the simulator hands each to a thread
        of its own (after a respawn beside a CPU hog a subscriber had waited 60 s)."""
        uri = rosgraph.Master("/faults").lookupNode(NODE)
        _code, _msg, proto = xmlrpc.client.ServerProxy(uri).requestTopic(
            "/faults", "/ePuck6/proximity2", [["TCPROS"]])
        stalled = socket.create_connection((proto[1], proto[2]))    # and says nothing
        try:
            fresh = Collector("/ePuck7/proximity3", Range)    # a topic not subscribed before
            fresh.wait(5, timeout_s=60)
            fresh.unregister()
        finally:
            stalled.close()

    def test_b_a_killed_client_restarts_and_gets_the_latched_state(self):
        first = start_client("--mode", "client", "--set-led")
        try:
            # the LED command went through: the client sees the latched state change to it
            deadline = time.monotonic() + 30
            line = wait_line(first, "LATCHED")
            while "LATCHED [1, 0, 1, 0, 1, 0, 1, 0, 1" not in line:
                self.assertLess(time.monotonic(), deadline, line)
                line = wait_line(first, "LATCHED")
        finally:
            first.send_signal(signal.SIGKILL)
            first.wait()
        clock = Collector("/clock", Clock)
        time.sleep(2.0)                        # the simulator notices the dead connections
        second = start_client("--mode", "client")
        try:
            line = wait_line(second, "LATCHED")
        finally:
            second.terminate()
            second.wait()
        self.assertIn("LATCHED [1, 0, 1, 0, 1, 0, 1, 0, 1", line)
        n = len(clock.messages)
        clock.wait(n + 20)                     # the simulator is still stepping

    def _private_master(self, port):
        uri = f"http://127.0.0.1:{port}"
        master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self._until(lambda: rosgraph.Master("/probe", master_uri=uri).is_online(), "master up")
        return master, uri

    def _until(self, condition, what, timeout_s=60.0):
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            try:
                if condition():
                    return
            except (OSError, rosgraph.MasterException):
                pass
            time.sleep(0.1)
        raise AssertionError(f"no {what} within {timeout_s} s")

    def _private_simulator(self, uri):
        env = dict(os.environ, ROS_MASTER_URI=uri, PYTHONFAULTHANDLER="1")
        sim = subprocess.Popen(["rosrun", "epuck_vrep_compat", "epuck_sim", "_n:=1"], env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        master = rosgraph.Master("/probe", master_uri=uri)

        def up():
            # its services are there, registered by this process: a simulator that exited
            # when the master restarted may have registered again with the new master first
            master.lookupService("/vrep/simRosGetObjectHandle")
            node = xmlrpc.client.ServerProxy(master.lookupNode(NODE))
            return node.getPid("/probe")[2] == sim.pid
        self._until(up, "simulator up")
        return sim

    @staticmethod
    def _exit_output(sim, timeout_s=60.0):
        """The simulator's output once it exits; a hung one is aborted (its threads' stacks
        end up in the output) and the test fails with that output."""
        try:
            return sim.communicate(timeout=timeout_s)[0]
        except subprocess.TimeoutExpired:
            sim.send_signal(signal.SIGABRT)
            out = sim.communicate()[0]
            raise AssertionError(f"the simulator did not exit in {timeout_s} s:\n{out}")

    def test_c_a_master_restart_or_loss_ends_the_simulator_with_status_3(self):
        port = free_port()
        master, uri = self._private_master(port)
        sim = self._private_simulator(uri)
        # restarted at once, as the simulator sees it: it is stopped while the master goes and
        # the new one comes up, which on a loaded machine may take longer than the 3 s after
        # which a master that does not answer counts as gone
        sim.send_signal(signal.SIGSTOP)
        try:
            master.terminate()                 # the new one knows nothing of /vrep
            master.wait()
            master, _ = self._private_master(port)
        finally:
            sim.send_signal(signal.SIGCONT)
        try:
            out = self._exit_output(sim)
            self.assertEqual(sim.returncode, 3, out)
            self.assertIn("restarted: /vrep's registrations are lost", out)
            sim = self._private_simulator(uri)  # and gone for good
        finally:
            master.terminate()
            master.wait()
        out = self._exit_output(sim)
        self.assertEqual(sim.returncode, 3, out)
        self.assertIn("has not answered for 3 s", out)

    def test_y_a_killed_simulator_respawns_and_subscribers_get_data_again(self):
        prox = Collector("/ePuck3/proximity0", Range)
        prox.wait(5)
        old = simulator_pid()
        os.kill(old, signal.SIGKILL)
        self._until(lambda: simulator_pid() != old, "respawned simulator")
        prox.clear()
        prox.wait(20, timeout_s=60)            # the subscriber from before receives again
        state = rospy.wait_for_message("/ePuck0/led_state", UInt8MultiArray, timeout=30)
        self.assertEqual(len(state.data), 10)   # latched state from the new simulator

    def test_zz_no_errors(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun("epuck_vrep_compat", "faults", Faults)

#!/usr/bin/python3
"""The simulator's speed-scale watchdog against a supervisor killed mid-walk (SIGKILL: it says
nothing on its way out): the IRB 140 stops within the watchdog's 0.25 s of simulated time after
the last scale, /IRB140/safety_stop says so and the log says it once; a fresh scale resumes the
arm; the SiX, not watched, never stops. The supervisor runs in lock-step (the simulator waits
for its answer to each step), so a loaded machine cannot trip the watchdog before the kill."""
import os
import signal
import time
import unittest
import xmlrpc.client

import rosgraph
import rospy
import rostest
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Float64

from sim_test_helpers import Collector, RosoutGuard, sim_time_now, wait_sim_time

TIMEOUT_S = 0.25
STEP_S = 0.05
MOVING_RAD_S = 0.01


def speed(msg):
    return max(abs(v) for v in msg.velocity)


class ScaleTimes:
    """The simulated time at which each /IRB140/speed_scale arrived."""

    def __init__(self):
        self.times = []
        self._sub = rospy.Subscriber("/IRB140/speed_scale", Float64,
                                     lambda _: self.times.append(sim_time_now()), queue_size=100)

    def connections(self):
        return self._sub.get_num_connections()


def kill_node(name):
    """SIGKILL the node (same machine): no unregistering, no last words."""
    master = rosgraph.Master("/test_speed_scale_watchdog")
    api = xmlrpc.client.ServerProxy(master.lookupNode(name))
    _, _, pid = api.getPid("/test_speed_scale_watchdog")
    os.kill(pid, signal.SIGKILL)


class SpeedScaleWatchdog(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_speed_scale_watchdog")
        cls.guard = RosoutGuard()
        cls.scales = ScaleTimes()
        cls.irb = Collector("/IRB140/joint_states", JointState)
        cls.six = Collector("/SIX/joint_states", JointState)
        cls.stop = Collector("/IRB140/safety_stop", Bool)
        wait_sim_time(1.0)

    def test_1_a_killed_supervisor_stops_the_arm_within_the_timeout(self):
        # the supervisor answers and the arm moves (its script, the operator far enough)
        deadline = time.monotonic() + 120
        while not (self.scales.times and self.irb.latest() is not None
                   and speed(self.irb.latest()) > MOVING_RAD_S):
            self.assertLess(time.monotonic(), deadline, "the IRB 140 never moved")
            time.sleep(0.05)
        self.stop.wait_for(lambda m: not m.data, what="safety_stop false while supervised")
        kill_node("/ssm_supervisor")
        # its connection closes after its last scale has been read: every scale it sent is in
        deadline = time.monotonic() + 60
        while self.scales.connections() > 0:
            self.assertLess(time.monotonic(), deadline, "the killed supervisor stayed connected")
            time.sleep(0.05)
        last_scale_s = self.scales.times[-1]
        stopped = self.stop.wait_for(lambda m: m.data, what="safety_stop true")
        self.assertTrue(stopped.data)
        # the arm holds from the first step past the timeout
        held = self.irb.wait_for(lambda m: speed(m) < MOVING_RAD_S and
                                 m.header.stamp.to_sec() > last_scale_s + TIMEOUT_S,
                                 what="the IRB 140 held")
        first_held = min(m.header.stamp.to_sec() for m in self.irb.messages
                         if m.header.stamp.to_sec() > last_scale_s and speed(m) < MOVING_RAD_S)
        rospy.loginfo("last scale at %.3f s, IRB 140 held from %.3f s", last_scale_s, first_held)
        self.assertLessEqual(first_held - last_scale_s, TIMEOUT_S + 2 * STEP_S + 1e-6)
        wait_sim_time(1.0)
        after = [m for m in self.irb.messages if m.header.stamp > held.header.stamp]
        self.assertGreater(len(after), 10)
        self.assertLess(max(speed(m) for m in after), MOVING_RAD_S)
        # the SiX is not watched: its script goes on
        self.assertGreater(max(speed(m) for m in self.six.messages[-20:]), MOVING_RAD_S)
        warnings = [w for w in self.guard.warnings if "protective stop until a fresh" in w]
        self.assertEqual(len(warnings), 1, warnings)
        self.assertIn("IRB140", warnings[0])

    def test_2_a_fresh_scale_resumes_it(self):
        pub = rospy.Publisher("/IRB140/speed_scale", Float64, queue_size=1)
        deadline = time.monotonic() + 60
        while True:                             # a supervisor of the test's own, answering
            pub.publish(Float64(1.0))
            last = self.stop.latest()
            if last is not None and not last.data and speed(self.irb.latest()) > MOVING_RAD_S:
                break
            self.assertLess(time.monotonic(), deadline, "the IRB 140 did not resume")
            time.sleep(0.02)

    def test_9_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun("epuck_vrep_compat", "test_speed_scale_watchdog", SpeedScaleWatchdog)

#!/usr/bin/python3
"""Every fault path of the simulator node, through the test-only fault hook (issue 27; the
hook is ``sim/fault_hook.py``, its services ``ros/node/fault_face.py``; the outcomes are
documented in docs/parameters.md, "When a step or a face fails"):

* a step that raises: the simulation pauses (``/vrep/info`` says so, time stands still) with an
  ERROR line naming the error, and ``simRosStartSimulation``, ``simRosStopSimulation`` then
  ``simRosStartSimulation``, and ``/vrep/reset`` then ``simRosStartSimulation`` each recover it;
* a step blocked for 1 s, far past its 50 ms budget: a WARN line says how far behind real time
  the simulation fell, that time is dropped (not caught up in a burst), and it runs on;
* a face whose publish raises on every step: one ERROR line naming the face and the error per
  5 s (throttled), the node stays up and every other face publishes on; switched off, the
  lines stop.
"""
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Range
from std_srvs.srv import Empty, SetBool
from vrep_common.msg import VrepInfo

from epuck_vrep_compat.compat import vrep_codes as vc
from sim_test_helpers import PKG, Collector, RosoutGuard, call, sim_time_now

STEP_FAILED = "simulation step failed"
STEP_ERROR = "InjectedFault: injected fault in a simulation step"
PUBLISH_ERROR = "FaultFace failed to publish"
LATE = "behind real time"


class FaultHook(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_fault_hook")
        cls.guard = RosoutGuard()
        cls.info = Collector("/vrep/info", VrepInfo)
        cls.clock = Collector("/clock", Clock)
        cls.proximity = Collector("/ePuck1/proximity3", Range)
        for name in ("raise_in_step", "block_step", "raise_in_publish"):
            rospy.wait_for_service(f"/vrep/fault/{name}", timeout=60)
        cls.raise_in_step = rospy.ServiceProxy("/vrep/fault/raise_in_step", Empty)
        cls.block_step = rospy.ServiceProxy("/vrep/fault/block_step", Empty)
        cls.raise_in_publish = rospy.ServiceProxy("/vrep/fault/raise_in_publish", SetBool)
        rospy.wait_for_service("/vrep/reset", timeout=60)
        cls.reset = rospy.ServiceProxy("/vrep/reset", Empty)
        cls.proximity.wait(1, timeout_s=60)

    def setUp(self):
        self.assertIn(call("simRosStartSimulation").result, (0, 1))
        self.advancing("before the test")

    def tearDown(self):
        self.raise_in_publish(False)

    # --- helpers --------------------------------------------------------------------------------
    def lines(self, kind, text, since=0):
        return [line for line in getattr(self.guard, kind)[since:] if text in line]

    def wait_line(self, kind, text, since, timeout_s=30.0):
        deadline = time.monotonic() + timeout_s
        while not self.lines(kind, text, since):
            if time.monotonic() > deadline:
                self.fail(f"no {kind[:-1]} line with '{text}' on /rosout within {timeout_s} s; "
                          f"got {getattr(self.guard, kind)[since:][-3:]}")
            time.sleep(0.05)
        return self.lines(kind, text, since)[0]

    def advancing(self, why, timeout_s=30.0):
        """/vrep/info reports running and its time grows; the proximity topic delivers."""
        n_info, n_range = len(self.info.messages), len(self.proximity.messages)
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            fresh = self.info.messages[n_info:]
            running = [m for m in fresh if m.simulatorState.data & 3 == vc.STATE_NOT_STOPPED]
            if len(running) >= 2 and running[-1].simulationTime.data > \
                    running[0].simulationTime.data and len(self.proximity.messages) > n_range:
                return
            time.sleep(0.05)
        self.fail(f"{why}: the simulation does not advance (last /vrep/info "
                  f"{self.info.latest()})")

    def fail_a_step(self):
        """A step raises: an ERROR line naming the error, and the simulation is paused."""
        since = len(self.guard.errors)
        self.raise_in_step()
        line = self.wait_line("errors", STEP_FAILED, since)
        self.assertIn(STEP_ERROR, line)
        paused = vc.STATE_NOT_STOPPED | vc.STATE_PAUSED
        self.assertEqual(call("simRosGetInfo").simulatorState & 3, paused)
        t0 = call("simRosGetInfo").simulationTime
        time.sleep(0.5)
        self.assertEqual(call("simRosGetInfo").simulationTime, t0, "time moves while paused")
        self.assertEqual(len(self.lines("errors", STEP_FAILED, since)), 1)

    # --- a step that raises -----------------------------------------------------------------------
    def test_a_failed_step_pauses_and_start_recovers(self):
        self.fail_a_step()
        self.assertEqual(call("simRosStartSimulation").result, 1)
        self.advancing("after simRosStartSimulation")

    def test_a_failed_step_pauses_and_stop_then_start_recover(self):
        self.fail_a_step()
        self.assertEqual(call("simRosStopSimulation").result, 1)
        self.assertEqual(call("simRosGetInfo").simulatorState & 3, 0)
        self.assertEqual(call("simRosStartSimulation").result, 1)
        self.advancing("after simRosStopSimulation and simRosStartSimulation")

    def test_a_failed_step_pauses_and_reset_then_start_recover(self):
        self.fail_a_step()
        self.reset()
        self.assertEqual(call("simRosStartSimulation").result, 1)
        self.advancing("after /vrep/reset and simRosStartSimulation")

    def test_two_failures_give_two_error_lines(self):
        since = len(self.guard.errors)
        self.fail_a_step()
        call("simRosStartSimulation")
        self.advancing("after the first failure")
        self.fail_a_step()
        self.assertEqual(len(self.lines("errors", STEP_FAILED, since)), 2)

    # --- a step past its budget -----------------------------------------------------------------
    def test_a_blocked_step_is_logged_and_its_time_dropped(self):
        since, errors_since = len(self.guard.warnings), len(self.guard.errors)
        s0, w0 = sim_time_now(), time.monotonic()
        self.block_step()
        self.wait_line("warnings", LATE, since)
        self.advancing("after the blocked step")
        time.sleep(2.0)
        s1, w1 = sim_time_now(), time.monotonic()
        # at most real time, less the second the step blocked (a burst of catch-up steps would
        # bring the simulation back to wall time)
        self.assertLess(s1 - s0, (w1 - w0) - 0.5, f"{s1 - s0:.2f} s simulated in "
                        f"{w1 - w0:.2f} s of wall time around a 1 s blocked step")
        self.assertEqual(call("simRosGetInfo").simulatorState & 3, vc.STATE_NOT_STOPPED)
        self.assertEqual(self.lines("errors", "", errors_since), [],
                         "an ERROR line for a late step")

    # --- a face that raises ---------------------------------------------------------------------
    def test_a_failing_face_is_logged_throttled_and_the_others_publish(self):
        since = len(self.guard.errors)
        self.assertTrue(self.raise_in_publish(True).success)
        line = self.wait_line("errors", PUBLISH_ERROR, since)
        self.assertIn("InjectedFault", line)
        self.clock.clear()
        self.proximity.clear()
        n_info = len(self.info.messages)
        time.sleep(3.0)
        self.assertGreater(len(self.clock.messages), 10, "/clock stopped with the face failing")
        self.assertGreater(len(self.proximity.messages), 10, "the e-puck's face stopped")
        running = [m for m in self.info.messages[n_info:]
                   if m.simulatorState.data & 3 == vc.STATE_NOT_STOPPED]
        self.assertGreater(len(running), 10, "/vrep/info stopped or is not running")
        # about 60 failures in those 3 s, at most one line per 5 s
        self.assertLessEqual(len(self.lines("errors", PUBLISH_ERROR, since)), 2)
        self.raise_in_publish(False)
        time.sleep(6.0)
        stopped_at = len(self.guard.errors)
        time.sleep(6.0)
        self.assertEqual(self.lines("errors", PUBLISH_ERROR, stopped_at), [],
                         "the face still fails after the fault was switched off")


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_fault_hook", FaultHook)

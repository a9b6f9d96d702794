#!/usr/bin/python3
"""merlin_safety.launch as a user runs it: operator_tracker's estimate feeds ssm_supervisor.
Over two walks into the IRB 140's workspace the arm is slowed, stopped and resumes, and while
it moves the true separation (the test's own /vrep/operator_separation queries) stays above C."""
import rospy
import rostest
from std_msgs.msg import Float64, String

from sim_test_helpers import Collector, SimTestCase
from test_ssm_supervisor import C_M, MOVING_RAD_S, WALK_CYCLE_S, WalkMonitor


class MerlinSafetyDemo(SimTestCase):
    NODE = "test_merlin_safety"
    SERVICES = ("/vrep/operator_separation",)
    FIRST_MESSAGE = ("/operator_tracker/pose", rospy.AnyMsg)
    MESSAGE_TIMEOUT_S = 60.0
    SIM_TIME_S = 1.0

    def test_1_slows_stops_resumes_and_holds_the_distance(self):
        scales = Collector("/ssm_supervisor/IRB140/scale", Float64)
        status = Collector("/ssm_supervisor/IRB140/status", String)
        samples = WalkMonitor().watch(2 * WALK_CYCLE_S)
        moving = [d for d, v in samples if v > MOVING_RAD_S]
        rospy.loginfo("tracked supervisor: min separation while moving %.3f m", min(moving))
        self.assertGreaterEqual(min(moving), C_M)
        values = [m.data for m in scales.messages]
        self.assertTrue(any(0.0 < v < 1.0 for v in values), "never slowed")
        first_stop = values.index(0.0)
        self.assertIn(1.0, values[first_stop:], "never resumed at full speed")
        self.assertTrue(any("protective stop" in m.data for m in status.messages))

    def test_9_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun("epuck_vrep_compat", "test_merlin_safety", MerlinSafetyDemo)

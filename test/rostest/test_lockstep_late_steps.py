#!/usr/bin/python3
"""Late steps for the experiment's row: a step the simulator takes in lock-step without the
answer of a controller that is still connected (hung, or slow beyond ``lockstep_timeout``)
counts in ``/experiment/late_steps/vrep``, where the experiment's probe adds it to the row's
``late_steps``; once the controller has gone, the steps it can no longer answer do not."""
import time

import rospy
import rostest

from epuck_vrep_compat.compat.topics import LATE_STEPS_PARAM
from sim_test_helpers import PKG, SimTestCase, stepped_robot


class LockstepLateSteps(SimTestCase):
    NODE = "test_lockstep_late_steps"
    GUARD = False

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        stepped_robot(cls)

    def late(self):
        return rospy.get_param(f"{LATE_STEPS_PARAM}/vrep", 0)

    def test_a_hung_controller_makes_late_steps_and_a_gone_one_does_not(self):
        self.assertTrue(self.step(1).success)       # step 1: not waited for
        self.assertEqual(self.late(), 0)
        for _ in range(3):                          # connected, silent: each step times out
            self.assertTrue(self.step(1).success)
        hung = self.late()
        self.assertGreaterEqual(hung, 2, "steps taken without a connected controller's answer")
        self.cmd.unregister()                       # the controller goes
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline:          # the simulator sees the connection close
            self.assertTrue(self.step(1).success)
            if self.late() == hung:
                break
            hung = self.late()
        for _ in range(3):
            self.assertTrue(self.step(1).success)
        self.assertEqual(self.late(), hung, "a gone controller's steps are not late")


if __name__ == "__main__":
    rostest.rosrun(PKG, "lockstep_late_steps", LockstepLateSteps)

#!/usr/bin/python3
"""Lock-step with a controller (``~lockstep_cmd_vel``): the first step is not waited for; each
later one waits for the robot's ``cmd_vel`` answering the step before (the simulator's own
subscriber has applied it), so the step uses it, however late it comes."""
import threading
import time

import rostest
from geometry_msgs.msg import Twist

from sim_test_helpers import PKG, SimTestCase, stepped_robot

V_M_S = 0.05


class CmdVelLockstep(SimTestCase):
    NODE = "test_cmd_vel_lockstep"

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        stepped_robot(cls)

    def _truth_at(self, sim_time):
        return self.truth.wait_for(lambda m: abs(m.header.stamp.to_sec() - sim_time) < 1e-6,
                                   what=f"the ground truth of t={sim_time}")

    def _command(self, v):
        cmd = Twist()
        cmd.linear.x = v
        self.cmd.publish(cmd)

    def test_each_step_waits_for_the_answer_to_the_last_and_uses_it(self):
        first = self.step(1)                        # not waited for: nothing answers step 0
        self.assertTrue(first.success, first.message)
        self.assertEqual(first.frame, 1)
        result = {}
        waiter = threading.Thread(target=lambda: result.setdefault("r", self.step(1)))
        waiter.start()
        time.sleep(1.0)      # the paused simulator would have stepped by now without lock-step
        self.assertTrue(waiter.is_alive(), "the step did not wait for step 1's cmd_vel")
        self._command(V_M_S)                        # the answer to step 1
        waiter.join(60.0)
        self.assertFalse(waiter.is_alive())
        second = result["r"]
        self.assertTrue(second.success, second.message)
        self.assertEqual(second.frame, 2)
        # step 2 ran the command: the robot moves at V_M_S in it
        twist = self._truth_at(second.sim_time).twist.twist.linear
        self.assertAlmostEqual((twist.x ** 2 + twist.y ** 2) ** 0.5, V_M_S, delta=0.1 * V_M_S)
        for k in range(3, 8):                       # a command right before each step
            self._command(0.0 if k % 2 else V_M_S)
            r = self.step(1)
            self.assertTrue(r.success, r.message)
            twist = self._truth_at(r.sim_time).twist.twist.linear
            self.assertAlmostEqual((twist.x ** 2 + twist.y ** 2) ** 0.5,
                                   0.0 if k % 2 else V_M_S, delta=0.1 * V_M_S)
        self.assertEqual(self.guard.errors, [])
        self.assertFalse([w for w in self.guard.warnings if "lockstep" in w],
                         "no step may be taken without its answer")


if __name__ == "__main__":
    rostest.rosrun(PKG, "cmd_vel_lockstep", CmdVelLockstep)

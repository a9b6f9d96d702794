#!/usr/bin/python3
"""The youBot's base under ssm_supervisor (youbot_safety.test): while the base drives at
0.2 m/s, S_p is larger than at rest by the fastest link point's speed over T_r + T_s / 2, and
that speed is the base's motion added to the wheels' spin (the supervisor's link speeds
include the base's own motion, from its root's twist on TF). When the operator (a recorded
trace: far away until 8 s, then by 11 s into the base's path, ahead of it) comes near, the
scale falls through (0, 1) to 0, and the base, still commanded at 0.2 m/s, stands still: it
stops short of him, the true separation above C."""
import threading

import numpy as np
import rospy
import rostest
from geometry_msgs.msg import Twist
from std_msgs.msg import Float64
from tf2_msgs.msg import TFMessage

from epuck_vrep_compat.srv import OperatorSeparation
from sim_test_helpers import PKG, Collector, SimTestCase, unpause_when_subscribed
from test_ssm_supervisor import C_M

SPEED_M_S = 0.2
T_R_S, T_S_S = 0.2, 0.3               # the supervisor's defaults


class BasePoses:
    """The youBot's base (x, y) on /tf, by stamp."""

    def __init__(self):
        self.poses = {}
        self._lock = threading.Lock()
        self._sub = rospy.Subscriber("/tf", TFMessage, self._cb, queue_size=1000)

    def _cb(self, msg):
        for t in msg.transforms:
            if t.child_frame_id == "youBot":
                with self._lock:
                    self.poses[t.header.stamp.to_sec()] = (t.transform.translation.x,
                                                           t.transform.translation.y)

    def speed(self, t0, t1):
        """Mean speed of the base between the stamps nearest t0 and t1."""
        with self._lock:
            stamps = np.array(sorted(self.poses))
            a = stamps[np.argmin(abs(stamps - t0))]
            b = stamps[np.argmin(abs(stamps - t1))]
            return float(np.hypot(*np.subtract(self.poses[b], self.poses[a]))) / (b - a)


class YoubotSafety(SimTestCase):
    NODE = "test_youbot_safety"

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.cmd = rospy.Publisher("/youBot/cmd_vel", Twist, queue_size=1)
        cls.s_p = Collector("/ssm_supervisor/youBot/protective_separation", Float64)
        cls.scale = Collector("/ssm_supervisor/youBot/scale", Float64)
        cls.base = BasePoses()
        rospy.wait_for_service("/vrep/operator_separation", timeout=60)
        # started paused (youbot_safety.test): the trace's clock starts once all is connected,
        # however long the start-up took on a loaded machine
        unpause_when_subscribed([cls.s_p._sub, cls.scale._sub, cls.base._sub])
        cls.s_p.wait(1, timeout_s=60)
        cls.scale.wait(1, timeout_s=60)

    def drive(self, vx, until_s):
        """Command vx until the simulated time; [(time, S_p, scale)] seen meanwhile."""
        seen = []
        while rospy.Time.now().to_sec() < until_s and not rospy.is_shutdown():
            self.cmd.publish(_twist(vx))
            seen.append((rospy.Time.now().to_sec(), self.s_p.latest().data,
                         self.scale.latest().data))
            rospy.sleep(0.1)
        return seen

    def test_1_the_base_counts_and_slows_and_stops(self):
        start = rospy.Time.now().to_sec()
        self.assertLess(start, 2.0, "the test started late: the trace's walk is under way")
        moving = self.drive(SPEED_M_S, 4.0)
        resting = self.drive(0.0, 6.0)
        s_p_moving = np.median([s for t, s, _ in moving if t > 3.0])
        s_p_rest = np.median([s for t, s, _ in resting if t > 5.0])
        # the arm stands still (its script stopped with the first command), so S_p grows by
        # v_r (T_r + T_s / 2), v_r the fastest closest point's speed: with the operator ahead,
        # the front of a wheel's rim, which turns down at 0.2 m/s while the base carries it
        # forward at 0.2 m/s: sqrt(2) 0.2 m/s. From the joint states alone (the wheels' spin)
        # it would be 0.2 m/s, and nothing else moves.
        v_r = (s_p_moving - s_p_rest) / (T_R_S + T_S_S / 2)
        rospy.loginfo("youBot: S_p %.3f m moving, %.3f m at rest: v_r %.3f m/s", s_p_moving,
                      s_p_rest, v_r)
        self.assertAlmostEqual(v_r, np.sqrt(2.0) * SPEED_M_S, delta=0.02)
        self.assertTrue(all(scale == 1.0 for t, _, scale in moving + resting if t > 2.0))
        self.assertAlmostEqual(self.base.speed(2.5, 3.5), SPEED_M_S, delta=0.01)
        first = len(self.scale.messages)
        approach = self.drive(SPEED_M_S, 16.0)
        # the stop: from when on the scale stays 0 (a one-cycle fail-safe 0 is not it)
        stop = next((t for k, (t, _, _) in enumerate(approach)
                     if all(scale == 0.0 for _, _, scale in approach[k:])), None)
        self.assertIsNotNone(stop, "never stopped for good")
        # every scale the supervisor sent meanwhile, not the 10 Hz samples above (which a
        # loaded machine thins out, and the slow-down lasts a few cycles)
        scales = [m.data for m in self.scale.messages[first:]]
        while scales and scales[-1] == 0.0:
            scales.pop()
        self.assertTrue(any(0.0 < s < 1.0 for s in scales), "never slowed before it stopped")
        # held: the base does not move while stopped (the command still asks for 0.2 m/s)
        held = [t for t, _, _ in approach if t > stop + 0.5]
        self.assertGreater(len(held), 10)
        self.assertLess(self.base.speed(held[0], held[-1]), 0.002)
        truth = rospy.ServiceProxy("/vrep/operator_separation", OperatorSeparation)(
            ground_truth=True)
        near = min(d for r, d in zip(truth.robot, truth.distance) if r == "youBot")
        rospy.loginfo("youBot stopped %.3f m from the operator", near)
        self.assertGreater(near, C_M)

    def test_9_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


def _twist(vx):
    t = Twist()
    t.linear.x = vx
    return t


if __name__ == "__main__":
    rostest.rosrun(PKG, "youbot_safety", YoubotSafety)

#!/usr/bin/python3
"""Each profile's defaults reproduce its original: launched with nothing but the profile (no
``cmd_vel_scaling``, no ``cmd_timeout``), a command in the original's own units drives the
robot at the speed the original gives it, and a command published once keeps the robot moving
for 10 s of simulated time (V-REP's script and the real driver's firmware keep the last wheel
speeds until the next command).

Test parameters: ``~profile`` and ``~robot`` (the robot's namespace). World
``test/worlds/empty.yaml``, noise off (exact kinematics), paused and stepped.
"""
import math
import time

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from epuck_vrep_compat.srv import StepSimulation
from sim_test_helpers import PKG, Collector, SimTestCase

WHEEL_RADIUS_M = 0.02


def vrep_speed(linear_x):
    """epuck_vrep_ros.lua: wheel = 8.9 * v / 40 applied as rad/s."""
    return 8.9 * linear_x / 40.0 * WHEEL_RADIUS_M


def driver_speed(linear_x):
    """epuck(2)_driver_cpp: v / 3, wheel = v / 4 rev/s, sent as whole motor steps (1000 per
    revolution)."""
    steps = int(linear_x / 3.0 / 4.0 * 1000.0)
    return steps / 1000.0 * 2.0 * math.pi * WHEEL_RADIUS_M


EXPECTED = {"vrep": vrep_speed, "epuck_driver": driver_speed, "epuck2_driver": driver_speed}
COMMAND_X = 2.0            # a typical driver- or script-tuned forward command


class ProfileDefaults(SimTestCase):
    NODE = "test_profile_defaults"
    SERVICES = ("/vrep/step",)

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.profile = rospy.get_param("~profile")
        cls.robot = rospy.get_param("~robot")
        cls.step = rospy.ServiceProxy("/vrep/step", StepSimulation, persistent=True)
        cls.truth = Collector(f"{cls.robot}/ground_truth", Odometry)
        cmd_topic = {"vrep": "cmd_vel"}.get(cls.profile, "mobile_base/cmd_vel")
        cls.cmd = rospy.Publisher(f"{cls.robot}/{cmd_topic}", Twist, queue_size=1)
        deadline = time.monotonic() + 60
        while cls.cmd.get_num_connections() == 0 and time.monotonic() < deadline:
            time.sleep(0.05)

    def _step(self, steps):
        result = self.step(steps)
        self.assertTrue(result.success, result.message)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            msg = self.truth.latest()
            if msg is not None and abs(msg.header.stamp.to_sec() - result.sim_time) < 1e-6:
                return msg
            time.sleep(0.01)
        self.fail(f"no ground truth stamped {result.sim_time}")

    def test_a_command_published_once_drives_at_the_originals_speed_for_10_s(self):
        start = self._step(1).pose.pose.position
        cmd = Twist()
        cmd.linear.x = COMMAND_X
        self.cmd.publish(cmd)     # once; nothing more is published during the 10 s
        time.sleep(0.5)           # delivery; the paused simulation does not advance meanwhile
        first = self._step(1).pose.pose.position
        after = self._step(200)   # 10 s of simulated time at the 50 ms step
        end = after.pose.pose.position
        speed = EXPECTED[self.profile](COMMAND_X)
        self.assertGreater(math.hypot(first.x - start.x, first.y - start.y), 0.0)
        travelled = math.hypot(end.x - first.x, end.y - first.y)
        # exact kinematics (noise off): the 10 s distance within 1 mm
        self.assertAlmostEqual(travelled, 10.0 * speed, delta=1e-3,
                               msg=f"{self.profile}: {travelled:.4f} m in 10 s, the original "
                               f"moves {10.0 * speed:.4f} m")
        self.assertAlmostEqual(after.twist.twist.linear.x, speed, delta=1e-4)

    def test_zz_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_profile_defaults", ProfileDefaults)

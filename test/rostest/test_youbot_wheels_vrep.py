#!/usr/bin/python3
"""The youBot's base driven as V-REP's youBot is driven: a /vrep client sets the four
rollingJoint_* target velocities (simRosSetJointTargetVelocity) and the base moves forward,
sideways and turns as the mecanum kinematics predict; /youBot/cmd_vel then takes it back.
Stepped synchronously, so the motion over a known number of steps is exact."""
import math
import time

import numpy as np
import rospy
import rostest
from geometry_msgs.msg import Twist, Vector3

from epuck_vrep_compat.cell.devices.mecanum import WHEELS, wheel_speeds
from sim_test_helpers import SimTestCase, call, handle

WORLD = -1
STEPS = 40


def base_pose(h):
    """(x, y, yaw) of an object in the world."""
    p = call("simRosGetObjectPose", handle=h, relativeToObjectHandle=WORLD).pose.pose
    q = p.orientation
    return np.array([p.position.x, p.position.y,
                     math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y ** 2 + q.z ** 2))])


def sim_time():
    return call("simRosGetInfo").simulationTime


def step(count):
    """Releases count synchronous steps, waiting for each to be taken."""
    for _ in range(count):
        before = call("simRosGetInfo").headerInfo.seq
        assert call("simRosSynchronousTrigger").result == 1
        deadline = time.monotonic() + 30
        while call("simRosGetInfo").headerInfo.seq == before:
            assert time.monotonic() < deadline, "the triggered step was never taken"
            time.sleep(0.005)


class YoubotWheels(SimTestCase):
    NODE = "test_youbot_wheels"
    SERVICES = ("/vrep/simRosSynchronousTrigger",)
    SIM_TIME_S = 0.5

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.bot = handle("youBot")
        cls.wheels = {w: handle(f"rollingJoint_{w}") for w in WHEELS}
        assert cls.bot >= 0 and min(cls.wheels.values()) >= 0
        assert call("simRosSynchronous", enable=1).result == 1

    @classmethod
    def tearDownClass(cls):
        call("simRosSynchronous", enable=0)

    def drive(self, twist):
        """Commands the wheels for twist (body frame), steps; returns the motion in the
        starting frame (forward, left, turned) and the simulated time it took."""
        for w, omega in wheel_speeds(*twist).items():
            res = call("simRosSetJointTargetVelocity", handle=self.wheels[w],
                       targetVelocity=omega)
            self.assertEqual(res.result, 1)
        step(1)                               # the commands take effect from this step on
        p0, t0 = base_pose(self.bot), sim_time()
        step(STEPS)
        p1, t1 = base_pose(self.bot), sim_time()
        c, s = math.cos(p0[2]), math.sin(p0[2])
        dx, dy = p1[0] - p0[0], p1[1] - p0[1]
        turned = math.atan2(math.sin(p1[2] - p0[2]), math.cos(p1[2] - p0[2]))
        return (c * dx + s * dy, -s * dx + c * dy, turned), t1 - t0

    def check(self, twist):
        (forward, left, turned), elapsed = self.drive(twist)
        self.assertGreater(elapsed, 0.0)
        vx, vy, wz = twist
        a = wz * elapsed
        if abs(a) < 1e-12:
            expected = (vx * elapsed, vy * elapsed)
        else:       # a constant body twist traces an arc
            expected = ((vx * math.sin(a) + vy * (math.cos(a) - 1)) / wz,
                        (vx * (1 - math.cos(a)) + vy * math.sin(a)) / wz)
        # the pose travels as float32 in the service answers; the steps' chords of the arc
        # differ from it by (wz dt)^2 / 24, relative
        self.assertAlmostEqual(forward, expected[0], delta=1e-4)
        self.assertAlmostEqual(left, expected[1], delta=1e-4)
        self.assertAlmostEqual(turned, a, delta=1e-4)

    def test_1_forward(self):
        self.check((0.2, 0.0, 0.0))

    def test_2_sideways(self):
        self.check((0.0, 0.15, 0.0))
        self.check((0.0, -0.1, 0.0))

    def test_3_rotating(self):
        self.check((0.0, 0.0, 0.6))

    def test_4_combined_then_stopped(self):
        self.check((0.1, -0.05, 0.3))
        self.check((0.0, 0.0, 0.0))

    def test_5_cmd_vel_still_drives_the_base(self):
        pub = rospy.Publisher("/youBot/cmd_vel", Twist, queue_size=10)
        deadline = time.monotonic() + 20
        while pub.get_num_connections() == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        pub.publish(Twist(linear=Vector3(0.0, 0.1, 0.0)))
        time.sleep(0.5)                       # delivered before the next step
        step(1)
        p0, t0 = base_pose(self.bot), sim_time()
        step(STEPS)
        p1, t1 = base_pose(self.bot), sim_time()
        left = -math.sin(p0[2]) * (p1[0] - p0[0]) + math.cos(p0[2]) * (p1[1] - p0[1])
        self.assertAlmostEqual(left, 0.1 * (t1 - t0), delta=1e-4)
        pub.publish(Twist())

    def test_9_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun("epuck_vrep_compat", "test_youbot_wheels", YoubotWheels)

#!/usr/bin/python3
"""Noise off, paused and stepped: motion matches the kinematics, IR matches the geometry.

World ``test/worlds/wall.yaml``: ePuck0 at (0.15, 0) facing +x, the wall's face at x = 0.20.
"""
import math
import time

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Imu, Range

from sim_test_helpers import PKG, Collector, SimTestCase, stepped_robot

WALL_X = 0.20
HALF_ANGLE = math.radians(15.0)
MAX_RANGE = 0.05


def yaw_of(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


class KinematicsAndSensors(SimTestCase):
    NODE = "test_kinematics_and_sensors"

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        stepped_robot(cls)

    def _step(self, steps):
        result = self.step(steps)
        self.assertTrue(result.success, result.message)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            msg = self.truth.latest()
            if msg is not None and abs(msg.header.stamp.to_sec() - result.sim_time) < 1e-6:
                return msg
            time.sleep(0.01)
        self.fail(f"no ground truth stamped {result.sim_time}")

    def _drive(self, v, w):
        cmd = Twist()
        cmd.linear.x, cmd.angular.z = v, w
        self.cmd.publish(cmd)
        time.sleep(0.3)           # delivery; the paused simulation does not advance meanwhile

    def _pose(self, msg):
        p = msg.pose.pose
        return p.position.x, p.position.y, yaw_of(p.orientation)

    def test_1_ir_at_known_wall_distance(self):
        start = self._step(1)
        x0, y0, yaw0 = self._pose(start)
        self.assertAlmostEqual(x0, 0.15, places=9)
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        readings = []
        for k in range(8):
            c = Collector(f"/ePuck0/proximity{k}", Range)
            time.sleep(0.3)
            self._step(1)
            readings.append(c.wait(1)[-1].range)
            c.unregister()
        for k in range(8):
            t = buf.lookup_transform("ePuck0/base_link", f"ePuck0/base_prox{k}", rospy.Time(0),
                                     rospy.Duration(5.0)).transform
            sensor_x = x0 + t.translation.x
            axis_angle = abs(yaw_of(t.rotation))
            expected = MAX_RANGE
            if axis_angle < math.pi / 2 + HALF_ANGLE:
                gap = max(0.0, axis_angle - HALF_ANGLE)
                d = (WALL_X - sensor_x) / math.cos(gap) if gap < math.pi / 2 else math.inf
                expected = min(d, MAX_RANGE)
            self.assertAlmostEqual(readings[k], expected, delta=0.001,
                                   msg=f"sensor {k}: {readings[k]} vs analytic {expected}")
        self.assertLess(readings[0], 0.02)     # front sensors see the wall at 1.5 cm
        self.assertAlmostEqual(readings[3], MAX_RANGE, places=6)   # float32 field

    def test_2_imu_at_rest(self):
        c = Collector("/ePuck0/imu", Imu)
        time.sleep(0.3)
        self._step(2)
        msg = c.wait(1)[-1]
        c.unregister()
        a = msg.linear_acceleration
        self.assertAlmostEqual(a.z, 9.81, places=6)
        self.assertAlmostEqual(a.x, 0.0, places=6)
        self.assertAlmostEqual(msg.angular_velocity.z, 0.0, places=6)

    def test_3_straight_then_arc(self):
        # back away from the wall first, then a straight line and an arc, 1 s each
        self._drive(-0.05, 0.0)
        x, y, yaw = self._pose(self._step(20))
        self._drive(0.0, 0.0)
        x, y, yaw = self._pose(self._step(1))
        self.assertAlmostEqual(x, 0.10, delta=1e-6)
        self._drive(-0.04, 0.0)
        x1, y1, yaw1 = self._pose(self._step(20))
        self.assertAlmostEqual(x1, x - 0.04, delta=1e-6)
        self.assertAlmostEqual(y1, y, delta=1e-6)
        v, w = 0.03, 0.5
        self._drive(v, w)
        x2, y2, yaw2 = self._pose(self._step(20))
        t = 1.0
        self.assertAlmostEqual(yaw2, yaw1 + w * t, delta=1e-6)
        self.assertAlmostEqual(x2, x1 + v / w * (math.sin(yaw1 + w * t) - math.sin(yaw1)),
                               delta=1e-6)
        self.assertAlmostEqual(y2, y1 - v / w * (math.cos(yaw1 + w * t) - math.cos(yaw1)),
                               delta=1e-6)

    def test_4_watchdog_stops_the_wheels(self):
        self._drive(0.02, 0.0)
        x0, y0, _ = self._pose(self._step(1))
        x1, y1, _ = self._pose(self._step(60))    # 3 s with no new command; timeout is 1 s
        travelled = math.hypot(x1 - x0, y1 - y0)
        self.assertGreater(travelled, 0.02 * 0.9)
        self.assertLess(travelled, 0.02 * 1.1)

    def test_zz_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_kinematics_and_sensors", KinematicsAndSensors)

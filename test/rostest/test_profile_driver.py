#!/usr/bin/python3
"""Profile epuck_driver, two robots: the real driver's names, types, frames and values."""
import numpy as np
import rospy
import rostest
import tf2_ros
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Image, Imu, LaserScan, Range
from visualization_msgs.msg import Marker

from epuck_vrep_compat.epuck import paper_robot as paper

from sim_test_helpers import PKG, SimTestCase, simulator_topics, wait_for_message

ROBOTS = ("epuck_robot_0", "epuck_robot_1")


class ProfileDriver(SimTestCase):
    NODE = "test_profile_driver"
    FIRST_MESSAGE = ("/clock", Clock)

    def test_topics_and_types(self):
        published, subscribed, types = simulator_topics()
        for robot in ROBOTS:
            expected = {f"/{robot}/proximity{k}": "sensor_msgs/Range" for k in range(8)}
            expected.update({f"/{robot}/scan": "sensor_msgs/LaserScan",
                             f"/{robot}/odom": "nav_msgs/Odometry",
                             f"/{robot}/accel": "sensor_msgs/Imu",
                             f"/{robot}/camera": "sensor_msgs/Image",
                             f"/{robot}/floor": "visualization_msgs/Marker",
                             f"/{robot}/microphone": "visualization_msgs/Marker",
                             f"/{robot}/motor_speed": "visualization_msgs/Marker"})
            for topic, msg_type in expected.items():
                self.assertIn(topic, published)
                self.assertEqual(types[topic], msg_type, topic)
            self.assertIn(f"/{robot}/mobile_base/cmd_vel", subscribed)
            self.assertIn(f"/{robot}/mobile_base/cmd_led", subscribed)
            self.assertNotIn(f"/{robot}/imu", published)

    def test_driver_values(self):
        msg = wait_for_message("/epuck_robot_1/proximity6", Range)
        self.assertEqual(msg.header.frame_id, "epuck_robot_1/base_prox6")
        self.assertAlmostEqual(msg.field_of_view, 0.26, places=6)
        self.assertAlmostEqual(msg.min_range, 0.005, places=6)
        self.assertAlmostEqual(msg.max_range, 0.05, places=6)
        scan = wait_for_message("/epuck_robot_0/scan", LaserScan)
        self.assertEqual(len(scan.ranges), 19)
        self.assertEqual(scan.header.frame_id, "epuck_robot_0/base_laser")
        self.assertAlmostEqual(scan.range_min, 0.04, places=6)
        self.assertAlmostEqual(scan.range_max, 0.085, places=6)
        odom = wait_for_message("/epuck_robot_0/odom", Odometry)
        self.assertEqual(odom.header.frame_id, "odom")
        self.assertEqual(odom.child_frame_id, "epuck_robot_0/base_link")
        accel = wait_for_message("/epuck_robot_0/accel", Imu)
        self.assertEqual(accel.header.frame_id, "epuck_robot_0/base_link")
        self.assertEqual(accel.orientation.w, 1.0)
        self.assertEqual(accel.orientation_covariance[0], -1.0)       # REP 145: no estimate
        self.assertEqual(accel.angular_velocity.z, 0.0)
        self.assertEqual(accel.angular_velocity_covariance[0], -1.0)  # no gyroscope
        np.testing.assert_allclose(np.reshape(accel.linear_acceleration_covariance, (3, 3)),
                                   np.diag(np.square(paper.ACCEL_STDDEV_M_S2)))
        self.assertAlmostEqual(accel.linear_acceleration.z, paper.TABLE1_REAL_MEAN_M_S2[2],
                               delta=0.3)

    def test_e_puck1_markers_and_camera_as_the_driver(self):
        robot = ROBOTS[0]
        floor = wait_for_message(f"/{robot}/floor", Marker)
        self.assertRegex(floor.text, r"^floor: \[\d+, \d+, \d+, 0, 0\]$")
        self.assertEqual(floor.header.frame_id, f"{robot}/base_link")
        mic = wait_for_message(f"/{robot}/microphone", Marker)
        self.assertEqual(mic.text, "mic: [0, 0, 0]")
        speed = wait_for_message(f"/{robot}/motor_speed", Marker)
        self.assertEqual(speed.text, "speed: [0, 0]")
        self.assertAlmostEqual(speed.pose.position.z, 0.15)
        image = wait_for_message(f"/{robot}/camera", Image, timeout_s=60)
        self.assertEqual((image.width, image.height, image.encoding), (160, 2, "mono8"))

    def test_tf(self):
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        for robot in ROBOTS:
            for child in ("base_link", "base_laser", "base_prox0", "left_wheel", "body_top"):
                buf.lookup_transform("odom", f"{robot}/{child}", rospy.Time(0),
                                     rospy.Duration(10.0))

    def test_zz_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_profile_driver", ProfileDriver)

#!/usr/bin/python3
"""Profile vrep, two robots: names, types, field values, rates, TF, LEDs and camera."""
import math

import numpy as np
import rospy
import rostest
import tf2_ros
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, Imu, Range
from std_msgs.msg import UInt8MultiArray

from epuck_vrep_compat.epuck import paper_robot as paper

from sim_test_helpers import (PKG, Collector, SimTestCase, simulator_topics, wait_for_message,
                              wait_sim_time)

ROBOTS = ("ePuck0", "ePuck1")


class ProfileVrep(SimTestCase):
    NODE = "test_profile_vrep"
    FIRST_MESSAGE = ("/clock", Clock)

    def test_topics_and_types(self):
        published, subscribed, types = simulator_topics()
        for robot in ROBOTS:
            expected = {f"/{robot}/proximity{k}": "sensor_msgs/Range" for k in range(8)}
            expected.update({f"/{robot}/imu": "sensor_msgs/Imu",
                             f"/{robot}/camera": "sensor_msgs/Image",
                             f"/{robot}/camera_info": "sensor_msgs/CameraInfo",
                             f"/{robot}/led_state": "std_msgs/UInt8MultiArray"})
            for topic, msg_type in expected.items():
                self.assertIn(topic, published)
                self.assertEqual(types[topic], msg_type, topic)
            self.assertIn(f"/{robot}/cmd_vel", subscribed)
            self.assertIn(f"/{robot}/cmd_led", subscribed)
            self.assertEqual(types[f"/{robot}/cmd_vel"], "geometry_msgs/Twist")
            self.assertNotIn(f"/{robot}/mobile_base/cmd_vel", subscribed)
        self.assertIn("/tf", published)
        self.assertIn("/clock", published)

    def test_range_fields_and_rate(self):
        for robot in ROBOTS:
            for k in (0, 3, 7):
                msg = wait_for_message(f"/{robot}/proximity{k}", Range)
                self.assertEqual(msg.header.frame_id, f"{robot}/base_prox{k}")
                self.assertEqual(msg.radiation_type, Range.INFRARED)
                self.assertAlmostEqual(msg.field_of_view, 0.52359878, places=6)
                self.assertAlmostEqual(msg.min_range, 0.0015, places=6)
                self.assertAlmostEqual(msg.max_range, 0.05, places=6)
                self.assertTrue(msg.min_range <= msg.range <= msg.max_range)
        c = Collector("/ePuck1/proximity4", Range)
        msgs = c.wait(41, timeout_s=30)
        stamps = np.array([m.header.stamp.to_sec() for m in msgs])
        # one message per 50 ms simulation step: 20 Hz in simulated time, no gaps
        np.testing.assert_allclose(np.diff(stamps), 0.05, atol=1e-6)

    def test_tf_tree(self):
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        timeout = rospy.Duration(10.0)
        for robot in ROBOTS:
            base = f"{robot}/base_link"
            buf.lookup_transform("odom", base, rospy.Time(0), timeout)
            children = [f"base_prox{k}" for k in range(8)] + ["left_wheel", "right_wheel",
                                                              "body_top", "camera_optical"]
            for child in children:
                t = buf.lookup_transform(base, f"{robot}/{child}", rospy.Time(0), timeout)
                self.assertEqual(t.header.frame_id, base)
            prox0 = buf.lookup_transform(base, f"{robot}/base_prox0", rospy.Time(0), timeout)
            self.assertAlmostEqual(prox0.transform.translation.z, 0.034, places=6)
            yaw = 2 * math.atan2(prox0.transform.rotation.z, prox0.transform.rotation.w)
            self.assertLess(yaw, 0.0)          # sensor 0 looks front-right

    def test_imu_at_rest_reads_specific_force(self):
        c = Collector("/ePuck1/imu", Imu)
        msgs = c.wait(60, timeout_s=30)
        z = np.array([m.linear_acceleration.z for m in msgs])
        x = np.array([m.linear_acceleration.x for m in msgs])
        # g plus the default bias: the paper's real robot (Table 1's means, 9.685 and -0.053)
        self.assertAlmostEqual(float(z.mean()), paper.TABLE1_REAL_MEAN_M_S2[2], delta=0.05)
        self.assertAlmostEqual(float(x.mean()), paper.TABLE1_REAL_MEAN_M_S2[0], delta=0.05)
        self.assertEqual(msgs[0].header.frame_id, "ePuck1/base_link")
        # REP 145: no orientation estimate; covariances are the noise model's variances
        # (the defaults: the accelerometer's own 0.0318, 0.0308, 0.0493 m/s^2, gyroscope 0.005)
        self.assertEqual(msgs[0].orientation_covariance[0], -1.0)
        self.assertEqual(msgs[0].orientation.w, 1.0)
        np.testing.assert_allclose(np.reshape(msgs[0].linear_acceleration_covariance, (3, 3)),
                                   np.diag(np.square(paper.ACCEL_STDDEV_M_S2)))
        np.testing.assert_allclose(np.reshape(msgs[0].angular_velocity_covariance, (3, 3)),
                                   np.diag(np.square([0.005] * 3)))

    def test_leds_latched(self):
        pub = rospy.Publisher("/ePuck0/cmd_led", UInt8MultiArray, queue_size=1, latch=True)
        pub.publish(UInt8MultiArray(data=bytes([1, 0, 1, 0, 0, 0, 0, 0, 1])))
        deadline = rospy.get_time() + 10.0
        state = None
        while rospy.get_time() < deadline:
            state = list(bytearray(wait_for_message("/ePuck0/led_state", UInt8MultiArray).data))
            if state[:9] == [1, 0, 1, 0, 0, 0, 0, 0, 1]:
                break
            wait_sim_time(0.1)
        self.assertEqual(state[:9], [1, 0, 1, 0, 0, 0, 0, 0, 1])

    def test_camera_image_and_info(self):
        img = wait_for_message("/ePuck0/camera", Image, timeout_s=30)
        self.assertEqual((img.width, img.height, img.encoding), (160, 120, "rgb8"))
        self.assertEqual(img.step, 3 * 160)
        self.assertEqual(len(img.data), 3 * 160 * 120)
        self.assertEqual(img.header.frame_id, "ePuck0/camera_optical")
        self.assertFalse(img.is_bigendian)
        pixels = np.frombuffer(img.data, dtype=np.uint8).reshape(120, 160, 3)
        self.assertGreater(len(np.unique(pixels.reshape(-1, 3), axis=0)), 2)  # not blank
        info = wait_for_message("/ePuck0/camera_info", CameraInfo)
        self.assertEqual((info.width, info.height), (160, 120))

    def test_zz_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_profile_vrep", ProfileVrep)

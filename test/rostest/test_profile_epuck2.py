#!/usr/bin/python3
"""Profile epuck2_driver (GCtronic epuck_driver_cpp, branch e-puck2, epuck2_driver_cpp.cpp):
every topic, type and frame of the driver's interface, values at known geometry, the LEDs,
bad input. World ``test/worlds/epuck2.yaml``, noise off, paused and stepped (50 ms steps);
``~microphone/levels`` [10, 20, 30, 40], ``~epuck2/battery_discharge_s`` 100.
"""
import math
import time

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import BatteryState, Image, Imu, LaserScan, MagneticField, Range
from std_msgs.msg import UInt8MultiArray
from visualization_msgs.msg import Marker, MarkerArray

from epuck_vrep_compat.srv import StepSimulation
from sim_test_helpers import PKG, Collector, SimTestCase, simulator_topics

ROBOTS = ("epuck_robot_0", "epuck_robot_1")
TOF_M = 0.465 / math.cos(0.21)        # both walls 0.465 m ahead of the pitched sensor
FLOOR_LIGHT = round(1000 * (0.85 + 0.85 + 0.8) / 3)   # the arena's default floor colour
DRIVER_COV = [0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01]


def yaw_of(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


PER_STEP_TOPICS = ("ground_truth", "battery", "dist_sens", "mag_field", "imu", "odom")


class ProfileEpuck2(SimTestCase):
    NODE = "test_profile_epuck2"
    SERVICES = ("/vrep/step",)

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.step_srv = rospy.ServiceProxy("/vrep/step", StepSimulation, persistent=True)
        cls.c = {}
        for robot in ROBOTS:
            for topic, cls_ in (("dist_sens", Range), ("mag_field", MagneticField),
                                ("mag_field_vector", Marker), ("battery", BatteryState),
                                ("floor", Marker), ("microphone", Marker), ("imu", Imu),
                                ("ground_truth", Odometry), ("led_state", UInt8MultiArray),
                                ("odom", Odometry)):
                cls.c[robot, topic] = Collector(f"/{robot}/{topic}", cls_)
        cls.markers = Collector("/vrep/markers", MarkerArray)
        cls.tf = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf)
        cls.cmd = rospy.Publisher("/epuck_robot_0/mobile_base/cmd_vel", Twist, queue_size=1)
        cls.rgb = rospy.Publisher("/epuck_robot_1/mobile_base/rgb_leds", UInt8MultiArray,
                                  queue_size=1)
        deadline = time.monotonic() + 60
        while (cls.cmd.get_num_connections() == 0 or cls.rgb.get_num_connections() == 0
               or any(c._sub.get_num_connections() == 0 for c in cls.c.values())):
            if time.monotonic() > deadline:
                raise AssertionError("the simulator's topics did not connect")
            time.sleep(0.05)

    def _step(self, steps=1):
        result = self.step_srv(steps)
        self.assertTrue(result.success, result.message)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            # every per-step topic read by the tests, each on its own connection
            if all(self._latest(r, t) is not None and
                   abs(self._latest(r, t).header.stamp.to_sec() - result.sim_time) < 1e-6
                   for r in ROBOTS for t in PER_STEP_TOPICS):
                return result.sim_time
            time.sleep(0.01)
        self.fail(f"no messages stamped {result.sim_time}")

    def _latest(self, robot, topic):
        return self.c[robot, topic].latest()

    def test_a_every_topic_and_type_of_the_driver(self):
        published, subscribed, types = simulator_topics()
        for robot in ROBOTS:
            expected = {f"proximity{k}": "sensor_msgs/Range" for k in range(8)}
            expected.update(scan="sensor_msgs/LaserScan", odom="nav_msgs/Odometry",
                            imu="sensor_msgs/Imu", camera="sensor_msgs/Image",
                            dist_sens="sensor_msgs/Range", mag_field="sensor_msgs/MagneticField",
                            mag_field_vector="visualization_msgs/Marker",
                            battery="sensor_msgs/BatteryState",
                            floor="visualization_msgs/Marker",
                            microphone="visualization_msgs/Marker")
            for name, msg_type in expected.items():
                self.assertIn(f"/{robot}/{name}", published)
                self.assertEqual(types[f"/{robot}/{name}"], msg_type, name)
            for name, msg_type in (("cmd_vel", "geometry_msgs/Twist"),
                                   ("cmd_led", "std_msgs/UInt8MultiArray"),
                                   ("rgb_leds", "std_msgs/UInt8MultiArray")):
                self.assertIn(f"/{robot}/mobile_base/{name}", subscribed)
                self.assertEqual(types[f"/{robot}/mobile_base/{name}"], msg_type)
            self.assertNotIn(f"/{robot}/accel", published)

    def test_b_fields_and_frames_as_the_driver(self):
        self._step()
        for robot in ROBOTS:
            tof = self._latest(robot, "dist_sens")
            self.assertEqual(tof.header.frame_id, f"{robot}/base_dist_sens")
            self.assertEqual(tof.radiation_type, Range.INFRARED)
            self.assertAlmostEqual(tof.field_of_view, 0.43, places=6)
            self.assertAlmostEqual(tof.min_range, 0.005, places=6)
            self.assertAlmostEqual(tof.max_range, 2.0, places=6)
            imu = self._latest(robot, "imu")
            self.assertEqual(imu.header.frame_id, f"{robot}/base_link")
            for cov in (imu.orientation_covariance, imu.angular_velocity_covariance,
                        imu.linear_acceleration_covariance):
                np.testing.assert_allclose(cov, DRIVER_COV)
            self.assertAlmostEqual(imu.linear_acceleration.z, 9.81, delta=0.05)
            self.assertAlmostEqual(abs(imu.orientation.w), 1.0, places=4)   # roll, pitch 0
            mag = self._latest(robot, "mag_field")
            self.assertEqual(mag.header.frame_id, f"{robot}/base_link")
            self.assertAlmostEqual(mag.magnetic_field_covariance[0], 0.01)
            arrow = self._latest(robot, "mag_field_vector")
            self.assertEqual(arrow.type, Marker.ARROW)
            self.assertEqual(len(arrow.points), 2)
            end = arrow.points[1]
            self.assertAlmostEqual(math.hypot(end.x, end.y), 1.0, places=6)
            mic = self._latest(robot, "microphone")
            self.assertEqual(mic.type, Marker.TEXT_VIEW_FACING)
            self.assertEqual(mic.text, "mic: [10, 20, 30, 40]")
            battery = self._latest(robot, "battery")
            self.assertTrue(battery.present)
            odom = self._latest(robot, "odom")
            self.assertEqual((odom.header.frame_id, odom.child_frame_id),
                             ("odom", f"{robot}/base_link"))
            np.testing.assert_allclose(np.diag(np.reshape(odom.pose.covariance, (6, 6))),
                                       [0.001, 0.001, 1000, 1000, 1000, 0.001])
            self.assertEqual(battery.header.frame_id, f"{robot}/base_link")
        for robot in ROBOTS:
            t = self._transform(f"{robot}/base_link", f"{robot}/base_dist_sens")
            self.assertAlmostEqual(t.translation.x, 0.035, places=6)
            self.assertAlmostEqual(t.translation.z, 0.034, places=6)
            pitch = 2 * math.atan2(t.rotation.y, t.rotation.w)
            self.assertAlmostEqual(pitch, -0.21, places=6)
            for child in ("base_laser", "base_prox0", "camera_optical"):
                self._transform("odom", f"{robot}/{child}")

    def _transform(self, parent, child):
        """The latest transform (paused: the clock stands still, so poll in wall time and step
        for fresh TF)."""
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            if self.tf.can_transform(parent, child, rospy.Time(0)):
                return self.tf.lookup_transform(parent, child, rospy.Time(0)).transform
            self._step()
            time.sleep(0.1)
        self.fail(f"no transform {parent} -> {child}")

    def test_c_tof_against_walls_at_known_distance(self):
        self._step()
        for robot in ROBOTS:
            self.assertAlmostEqual(self._latest(robot, "dist_sens").range, TOF_M, delta=1e-6)

    def test_d_ground_sensors_over_two_floor_colours(self):
        self._step()
        self.assertEqual(self._latest("epuck_robot_0", "floor").text,
                         f"floor: [{FLOOR_LIGHT}, {FLOOR_LIGHT}, {FLOOR_LIGHT}]")
        self.assertEqual(self._latest("epuck_robot_1", "floor").text, "floor: [0, 0, 0]")

    def test_e_battery_falls_over_time(self):
        t0 = self._step()
        v0 = self._latest("epuck_robot_0", "battery").voltage
        t1 = self._step(100)                        # 5 s
        b1 = self._latest("epuck_robot_0", "battery")
        self.assertAlmostEqual(v0, 4.2 - 0.8 * t0 / 100.0, delta=1e-5)
        self.assertAlmostEqual(b1.voltage, 4.2 - 0.8 * t1 / 100.0, delta=1e-5)
        self.assertLess(b1.voltage, v0 - 0.039)
        self.assertAlmostEqual(b1.percentage, (b1.voltage - 3.4) / 0.8, delta=1e-5)

    def test_f_magnetometer_heading_after_a_90_degree_turn(self):
        self._step()
        before = self._latest("epuck_robot_0", "mag_field").magnetic_field
        yaw0 = yaw_of(self._latest("epuck_robot_0", "ground_truth").pose.pose.orientation)
        cmd = Twist()
        cmd.angular.z = 3.0                   # driver units: 662 steps/s, 3.139 rad/s
        self.cmd.publish(cmd)
        time.sleep(0.5)
        self._step(10)                        # 0.5 s: 1.5696 rad
        self.cmd.publish(Twist())
        time.sleep(0.5)
        self._step(1)
        after = self._latest("epuck_robot_0", "mag_field").magnetic_field
        yaw1 = yaw_of(self._latest("epuck_robot_0", "ground_truth").pose.pose.orientation)
        heading = [math.atan2(-m.y, m.x) for m in (before, after)]   # field north along +x
        self.assertAlmostEqual(heading[0], yaw0, delta=1e-6)
        self.assertAlmostEqual(heading[1], yaw1, delta=1e-6)
        self.assertAlmostEqual(heading[1] - heading[0], math.pi / 2, delta=0.02)
        self.assertAlmostEqual(after.z, before.z, delta=1e-12)

    def test_g_rgb_leds_reach_led_state_and_the_markers(self):
        self.rgb.publish(UInt8MultiArray(data=bytes([100, 0, 0, 0, 0, 0, 0, 50, 0, 0, 0, 0])))
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            state = self._latest("epuck_robot_1", "led_state")
            if state is not None and bytearray(state.data)[1] == 1:
                break
            self._step()
        self.assertEqual([bytearray(state.data)[k] for k in (1, 3, 5, 7)], [1, 0, 1, 0])
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:        # the markers follow in the same pass
            markers = self.markers.wait_for(lambda m: True, what="a marker array")
            leds = {m.id: m.color for m in markers.markers if m.ns == "epuck_robot_1/leds"}
            if leds and leds[1].r == 1.0:
                break
            time.sleep(0.1)
        self.assertEqual((leds[1].r, leds[1].g, leds[1].b), (1.0, 0.0, 0.0))
        self.assertEqual((leds[5].r, leds[5].g, leds[5].b), (0.0, 0.5, 0.0))

    def test_h_bad_input_is_refused_and_the_simulation_goes_on(self):
        before = bytes(self._latest("epuck_robot_1", "led_state").data)
        self.rgb.publish(UInt8MultiArray(data=bytes([1, 2, 3, 4, 5])))
        nan = Twist()
        nan.linear.x = float("nan")
        self.cmd.publish(nan)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and not (
                any("rgb_leds needs exactly 12 bytes" in w for w in self.guard.warnings)
                and any("non-finite" in w for w in self.guard.warnings)):
            time.sleep(0.1)
        self.assertTrue(any("epuck_robot_1: rgb_leds needs exactly 12 bytes" in w
                            for w in self.guard.warnings), self.guard.warnings)
        self.assertTrue(any("epuck_robot_0: cmd_vel with a non-finite value" in w
                            for w in self.guard.warnings), self.guard.warnings)
        t = self._step(2)
        self.assertGreater(t, 0.0)
        self.assertEqual(bytes(self._latest("epuck_robot_1", "led_state").data), before)
        pose = self._latest("epuck_robot_0", "ground_truth").pose.pose.position
        self.assertTrue(math.isfinite(pose.x) and math.isfinite(pose.y))

    def test_i_camera_default_is_the_drivers_160_by_2_grey_slice(self):
        images = Collector("/epuck_robot_0/camera", Image)
        deadline = time.monotonic() + 60
        while not images.messages and time.monotonic() < deadline:
            self._step(5)
            time.sleep(0.1)
        image = images.wait(1)[0]
        self.assertEqual((image.width, image.height, image.encoding, image.step),
                         (160, 2, "mono8", 160))
        self.assertEqual(len(image.data), 320)

    def test_j_robot_description_links_are_the_tf_frames(self):
        import xml.etree.ElementTree as ET
        for robot in ROBOTS:
            urdf = ET.fromstring(rospy.get_param(f"/{robot}/robot_description"))
            links = {link.get("name") for link in urdf.iter("link")}
            self.assertIn(f"{robot}/base_link", links)
            self.assertIn(f"{robot}/base_dist_sens", links)
            self.assertIn(f"{robot}/left_wheel", links)
            for link in links:
                self._transform(f"{robot}/base_link", link)

    def test_zz_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_profile_epuck2", ProfileEpuck2)

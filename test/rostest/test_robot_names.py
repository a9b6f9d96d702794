#!/usr/bin/python3
"""Any robot names (launch argument ``names``): topics and TF frames follow the names, V-REP's
object names stay V-REP's, a name the original would not give works with a warning, and an
unusable names list stops a simulator with exit 2 naming it, while this one keeps running.

Test parameters: ``~robots`` (the names launched), ``~frames`` (their frame prefixes),
``~cmd_vel`` (the command topic under a robot's namespace).
"""
import subprocess
import time

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Range

from sim_test_helpers import (PKG, Collector, SimTestCase, handle, simulator_topics,
                              wait_for_message)


def topic(robot, name):
    return f"/{name}" if robot == "/" else f"/{robot}/{name}"


class RobotNames(SimTestCase):
    NODE = "test_robot_names"
    FIRST_MESSAGE = ("/clock", Clock)
    MESSAGE_TIMEOUT_S = 60.0

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.robots = rospy.get_param("~robots")
        cls.frames = rospy.get_param("~frames")
        cls.cmd_vel = rospy.get_param("~cmd_vel")

    def test_a_topics_follow_the_names(self):
        published, subscribed, types = simulator_topics()
        for robot in self.robots:
            for k in range(8):
                self.assertIn(topic(robot, f"proximity{k}"), published)
            self.assertIn(topic(robot, self.cmd_vel), subscribed)
        msg = wait_for_message(topic(self.robots[-1], "proximity0"), Range)
        self.assertEqual(msg.header.frame_id, f"{self.frames[-1]}/base_prox0")

    def test_b_tf_frames_follow_the_names(self):
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        for prefix in self.frames:
            for child in ("base_link", "base_prox0", "camera_optical"):
                buf.lookup_transform("odom", f"{prefix}/{child}", rospy.Time(0),
                                     rospy.Duration(20.0))

    def test_b2_robot_description_follows_the_names(self):
        import xml.etree.ElementTree as ET
        for robot, prefix in zip(self.robots, self.frames):
            param = "/robot_description" if robot == "/" else f"/{robot}/robot_description"
            urdf = ET.fromstring(rospy.get_param(param))
            links = {link.get("name") for link in urdf.iter("link")}
            self.assertIn(f"{prefix}/base_link", links)
            self.assertTrue(all(link.startswith(prefix + "/") for link in links), links)

    def test_c_vrep_object_names_stay_vreps(self):
        for k in range(len(self.robots)):
            suffix = "" if k == 0 else f"#{k - 1}"
            self.assertGreaterEqual(handle("ePuck" + suffix), 0)
            self.assertGreaterEqual(handle("ePuck_proxSensor0" + suffix), 0)

    def test_d_each_name_drives_its_own_robot(self):
        robot = self.robots[-1]
        truth = Collector(topic(robot, "ground_truth"), Odometry)
        pub = rospy.Publisher(topic(robot, self.cmd_vel), Twist, queue_size=1)
        deadline = time.monotonic() + 30
        while pub.get_num_connections() == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        start = truth.wait(1, timeout_s=30)[-1].pose.pose.position
        cmd = Twist()
        cmd.linear.x = 1.0
        pub.publish(cmd)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            now = truth.latest().pose.pose.position
            if abs(now.x - start.x) + abs(now.y - start.y) > 0.005:
                break
            time.sleep(0.05)
        else:
            self.fail(f"{robot} did not move on {topic(robot, self.cmd_vel)}")
        pub.publish(Twist())

    def test_e_unconventional_names_are_warned_about(self):
        # a simulator of its own, stopped at start-up by another parameter after the names
        proc = subprocess.run(["rosrun", PKG, "epuck_sim", "__name:=odd_names",
                               "_profile:=epuck_driver", "_robot_names:=[leader, epuck_robot_2]",
                               "_rtf:=-1.0"], capture_output=True, text=True, timeout=120)
        output = proc.stdout + proc.stderr
        self.assertEqual(proc.returncode, 2, output)
        self.assertIn("~robot_names: leader not named as the epuck_driver original", output)
        self.assertNotIn("epuck_robot_2 not named", output)

    def test_f_an_unusable_names_list_exits_2_naming_it(self):
        cases = [("_robot_names:=[epuck_1, epuck_1]", "twice"),
                 ("_robot_names:=[epuck-1]", "epuck-1"),
                 ("_robot_names:=[/, epuck_2]", "only name"),
                 ("_robot_names:=[42]", "42")]
        for k, (arg, says) in enumerate(cases):
            proc = subprocess.run(["rosrun", PKG, "epuck_sim", f"__name:=bad_names_{k}", arg],
                                  capture_output=True, text=True, timeout=120)
            output = proc.stdout + proc.stderr
            self.assertEqual(proc.returncode, 2, f"{arg}: {output}")
            self.assertIn("~robot_names", output, arg)
            self.assertIn(says, output, arg)
        # the simulator under test keeps running
        before = rospy.get_rostime()
        wait_for_message("/clock", Clock)
        deadline = time.monotonic() + 30
        while rospy.get_rostime() <= before and time.monotonic() < deadline:
            time.sleep(0.05)
        self.assertGreater(rospy.get_rostime(), before)

    def test_zz_no_errors_logged(self):
        self.assertEqual([e for e in self.guard.errors if e.startswith("/vrep")], [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_robot_names", RobotNames)

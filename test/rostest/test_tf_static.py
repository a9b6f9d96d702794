#!/usr/bin/python3
"""/tf_static with two e-pucks: what never moves relative to its parent is latched on
/tf_static (as robot_state_publisher does), only base_link and the wheels go on /tf each step;
tf and tf2 listeners see the whole tree, also when they start late; a robot loaded or removed
through /vrep updates /tf_static."""
import time

import rospy
import rostest
import tf
import tf2_ros
from rosgraph_msgs.msg import Clock
from tf2_msgs.msg import TFMessage

from sim_test_helpers import PKG, Collector, SimTestCase, call, wait_for_message, wait_sim_time

ROBOTS = ("ePuck0", "ePuck1")
FIXED = [f"base_prox{k}" for k in range(8)] + ["body_top", "camera_optical"]
MOVING = ["base_link", "left_wheel", "right_wheel"]
TIMEOUT_S = 60.0


def latched():
    """A fresh subscription's first /tf_static message (the latched one)."""
    return wait_for_message("/tf_static", TFMessage, timeout_s=TIMEOUT_S)


def children(msg):
    return {t.child_frame_id for t in msg.transforms}


class TfStatic(SimTestCase):
    NODE = "test_tf_static"
    FIRST_MESSAGE = ("/clock", Clock)
    MESSAGE_TIMEOUT_S = TIMEOUT_S

    def test_fixed_frames_latched_moving_frames_per_step(self):
        static = latched()
        self.assertEqual(children(static), {f"{r}/{c}" for r in ROBOTS for c in FIXED})
        for t in static.transforms:
            self.assertEqual(t.header.frame_id, t.child_frame_id.split("/")[0] + "/base_link")
        per_step = Collector("/tf", TFMessage)
        msgs = per_step.wait(5, timeout_s=TIMEOUT_S)
        per_step.unregister()
        for msg in msgs:
            self.assertEqual(children(msg), {f"{r}/{c}" for r in ROBOTS for c in MOVING})

    def test_tf2_listener_sees_the_whole_tree(self):
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        for robot in ROBOTS:
            t = buf.lookup_transform("odom", f"{robot}/camera_optical", rospy.Time(0),
                                     rospy.Duration(TIMEOUT_S))
            self.assertEqual(t.child_frame_id, f"{robot}/camera_optical")
            fixed = buf.lookup_transform(f"{robot}/base_link", f"{robot}/base_prox3",
                                         rospy.Time(0), rospy.Duration(TIMEOUT_S))
            sent = [s for s in latched().transforms
                    if s.child_frame_id == f"{robot}/base_prox3"][0]
            self.assertAlmostEqual(fixed.transform.translation.x,
                                   sent.transform.translation.x, places=9)
            self.assertAlmostEqual(fixed.transform.rotation.z, sent.transform.rotation.z,
                                   places=9)

    def test_tf_listener_that_starts_late_sees_the_fixed_frames(self):
        wait_sim_time(1.0)
        listener = tf.TransformListener()
        for robot in ROBOTS:
            listener.waitForTransform(f"{robot}/base_link", f"{robot}/body_top", rospy.Time(0),
                                      rospy.Duration(TIMEOUT_S))
            (x, y, z), _q = listener.lookupTransform(f"{robot}/base_link", f"{robot}/body_top",
                                                     rospy.Time(0))
            self.assertGreater(z, 0.0)
            listener.waitForTransform("odom", f"{robot}/base_prox0", rospy.Time(0),
                                      rospy.Duration(TIMEOUT_S))

    def test_robots_loaded_and_removed_update_tf_static(self):
        before = children(latched())
        handle = call("simRosLoadModel", fileName="ePuck.ttm").baseHandle
        self.assertGreater(handle, 0)
        deadline = time.monotonic() + TIMEOUT_S
        added = set()
        while time.monotonic() < deadline and len(added) < len(FIXED):
            added = children(latched()) - before
            time.sleep(0.1)
        self.assertEqual(len(added), len(FIXED), added)
        self.assertEqual({name.split("/", 1)[1] for name in added}, set(FIXED))
        self.assertGreater(call("simRosRemoveModel", handle=handle).result, 0)
        deadline = time.monotonic() + TIMEOUT_S
        while time.monotonic() < deadline and children(latched()) != before:
            time.sleep(0.1)
        self.assertEqual(children(latched()), before)

    def test_zz_no_error_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "tf_static", TfStatic)

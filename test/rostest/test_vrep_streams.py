#!/usr/bin/python3
"""The /vrep streams: enable/disable with reference counting, what the publisher streams send
once per step, subscriber streams acting on the simulation, and every stream ending when the
simulation stops (V-REP 3.3.0's legacy plugin)."""
import math
import time

import numpy as np
import rosgraph.masterapi
import rospy
import rostest
from geometry_msgs.msg import Point, PoseStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, Image, JointState, PointCloud2
from std_msgs.msg import Int32
from tf2_msgs.msg import TFMessage
from vrep_common.msg import JointSetStateData, ProximitySensorData
from vrep_common.srv import (
    simRosDisablePublisher, simRosDisableSubscriber, simRosEnablePublisher,
    simRosEnableSubscriber, simRosGetObjectHandle, simRosStartSimulation, simRosStopSimulation)

from sim_test_helpers import PKG, Collector, SimTestCase, wait_for_message, wait_sim_time

# simros_strmcmd_* (v_repConst.h, as clients hard-code them)
GET_JOINT_STATE, GET_OBJECT_POSE, GET_TRANSFORM = 4102, 8193, 8198
GET_VISION_SENSOR_IMAGE, GET_VISION_SENSOR_INFO, GET_DEPTH_SENSOR_DATA = 4108, 4114, 4118
READ_PROXIMITY_SENSOR, GET_INTEGER_SIGNAL = 4112, 12290
SET_JOINT_STATE, SET_OBJECT_POSITION, SET_INTEGER_SIGNAL = 2051, 10244, 14341
HANDLE_ALL, HANDLE_PARENT, WORLD = -2, -11, -1
STEP_S = 0.05


def service(name, srv_class):
    rospy.wait_for_service("/vrep/" + name, timeout=30.0)
    return rospy.ServiceProxy("/vrep/" + name, srv_class)


def vrep_topics():
    master = rosgraph.masterapi.Master(rospy.get_name())
    pubs, subs, _ = master.getSystemState()
    return ({t for t, nodes in pubs if "/vrep" in nodes},
            {t for t, nodes in subs if "/vrep" in nodes})


class VrepStreams(SimTestCase):
    NODE = "test_vrep_streams"
    GUARD = False

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.enable_pub = service("simRosEnablePublisher", simRosEnablePublisher)
        cls.disable_pub = service("simRosDisablePublisher", simRosDisablePublisher)
        cls.enable_sub = service("simRosEnableSubscriber", simRosEnableSubscriber)
        cls.disable_sub = service("simRosDisableSubscriber", simRosDisableSubscriber)
        get_handle = service("simRosGetObjectHandle", simRosGetObjectHandle)
        cls.h = {name: get_handle(name).handle for name in (
            "ePuck", "ePuck_leftJoint", "ePuck_rightJoint", "ePuck_camera",
            "ePuck_proxSensor0", "probe_box")}
        assert min(cls.h.values()) > 0, cls.h
        wait_for_message("/vrep/info", rospy.AnyMsg)

    def publisher(self, name, cmd, a1=0, a2=0, s=""):
        return self.enable_pub(name, 1, cmd, a1, a2, s).effectiveTopicName

    def subscriber(self, name, cmd, a1=0, a2=0, s=""):
        return self.enable_sub(name, 1, cmd, a1, a2, s).subscriberID

    def drive(self, speeds, topic="/test_vrep_streams/wheels"):
        """Wheel speeds through a set_joint_state subscriber stream; returns its ID."""
        sid = self.subscriber(topic, SET_JOINT_STATE)
        self.assertGreaterEqual(sid, 0)
        pub = rospy.Publisher(topic, JointSetStateData, queue_size=1)
        msg = JointSetStateData()
        msg.handles.data = [self.h["ePuck_leftJoint"], self.h["ePuck_rightJoint"]]
        msg.setModes.data = [2, 2]
        msg.values.data = list(speeds)
        deadline = time.monotonic() + 10.0
        while pub.get_num_connections() == 0 and time.monotonic() < deadline:
            time.sleep(0.01)
        for _ in range(5):
            pub.publish(msg)
            time.sleep(0.05)
        return sid, pub

    def test_enable_disable_reference_counting(self):
        left = self.h["ePuck_leftJoint"]
        self.assertEqual(self.publisher("rc", GET_JOINT_STATE, HANDLE_ALL), "rc")
        self.assertEqual(self.publisher("other", GET_JOINT_STATE, HANDLE_ALL), "rc")
        self.assertEqual(self.publisher("rc", GET_JOINT_STATE, left), "rc_2")
        self.assertEqual(self.publisher("info", GET_JOINT_STATE, left, 0, "x"), "rc_2")
        self.assertEqual(self.publisher("e-puck#0", GET_OBJECT_POSE, left, WORLD),
                         "e_MINUSMARK_puck_HASHMARK_0")
        self.assertEqual(self.publisher("x", GET_JOINT_STATE, 99999), "")
        self.assertEqual(self.publisher("", GET_JOINT_STATE, HANDLE_ALL), "")
        self.assertEqual(self.publisher("x", SET_JOINT_STATE), "")
        published, _ = vrep_topics()
        self.assertIn("/vrep/rc", published)
        self.assertEqual(self.disable_pub("rc").referenceCounter, 1)
        self.assertEqual(self.disable_pub("rc").referenceCounter, 0)
        self.assertEqual(self.disable_pub("rc").referenceCounter, -1)
        for name in ("rc_2", "rc_2", "e_MINUSMARK_puck_HASHMARK_0"):
            self.assertGreaterEqual(self.disable_pub(name).referenceCounter, 0)
        self.assertNotIn("/vrep/rc", vrep_topics()[0])

    def test_joint_state_once_per_step(self):
        topic = self.publisher("joints", GET_JOINT_STATE, HANDLE_ALL)
        msgs = Collector("/vrep/" + topic, JointState).wait(21)
        self.assertEqual(msgs[0].name, ["ePuck_leftJoint", "ePuck_rightJoint"])
        self.assertEqual(len(msgs[0].position), 2)
        stamps = np.array([m.header.stamp.to_sec() for m in msgs])
        np.testing.assert_allclose(np.diff(stamps), STEP_S, atol=1e-6)
        seqs = np.array([m.header.seq for m in msgs])
        np.testing.assert_array_equal(np.diff(seqs), 1)          # V-REP's frame id
        self.assertEqual(self.disable_pub(topic).referenceCounter, 0)

    def test_object_pose_matches_ground_truth(self):
        topic = self.publisher("pose", GET_OBJECT_POSE, self.h["ePuck"], WORLD, "world")
        poses = Collector("/vrep/" + topic, PoseStamped)
        truth = Collector("/ePuck0/ground_truth", Odometry)
        poses.wait(5)
        truth.wait(5)
        pose, odom = poses.latest(), truth.latest()
        self.assertEqual(pose.header.frame_id, "world")
        same = [o for o in truth.messages if o.header.stamp == pose.header.stamp]
        reference = (same or [odom])[0].pose.pose.position
        self.assertAlmostEqual(pose.pose.position.x, reference.x, delta=0.01)
        self.assertAlmostEqual(pose.pose.position.y, reference.y, delta=0.01)
        self.disable_pub(topic)

    def test_vision_image_info_and_depth_cloud(self):
        camera = self.h["ePuck_camera"]
        image_topic = self.publisher("image", GET_VISION_SENSOR_IMAGE, camera)
        info_topic = self.publisher("camera_info", GET_VISION_SENSOR_INFO, camera)
        cloud_topic = self.publisher("cloud", GET_DEPTH_SENSOR_DATA, camera)
        images = Collector("/vrep/" + image_topic, Image).wait(3)
        info = wait_for_message("/vrep/" + info_topic, CameraInfo)
        cloud = wait_for_message("/vrep/" + cloud_topic, PointCloud2)
        image = images[-1]
        self.assertEqual((image.encoding, image.step), ("rgb8", 3 * image.width))
        self.assertEqual(image.header.frame_id, "/ePuck_camera")
        self.assertEqual(len(image.data), 3 * image.width * image.height)
        self.assertAlmostEqual(images[1].header.stamp.to_sec() - images[0].header.stamp.to_sec(),
                               STEP_S, places=6)
        self.assertEqual((info.width, info.height), (image.width, image.height))
        self.assertEqual(info.header.frame_id, "/ePuck_camera")
        self.assertEqual(info.K[2], image.width // 2)
        self.assertEqual((cloud.width, cloud.height, cloud.point_step),
                         (image.width, image.height, 16))
        self.assertEqual([f.name for f in cloud.fields], ["x", "y", "z", "rgb"])
        self.assertEqual(len(cloud.data), 16 * image.width * image.height)
        for topic in (image_topic, info_topic, cloud_topic):
            self.assertEqual(self.disable_pub(topic).referenceCounter, 0)

    def test_proximity_only_while_detected(self):
        sid = self.subscriber("box_position", SET_OBJECT_POSITION, self.h["probe_box"], WORLD)
        self.assertGreaterEqual(sid, 0)
        mover = rospy.Publisher("/vrep/box_position", Point, queue_size=1)
        topic = self.publisher("prox", READ_PROXIMITY_SENSOR, self.h["ePuck_proxSensor0"])
        prox = Collector("/vrep/" + topic, ProximitySensorData)
        pose = wait_for_message("/ePuck0/ground_truth", Odometry).pose.pose
        wait_sim_time(0.5)
        self.assertEqual(prox.messages, [])                 # nothing within 5 cm
        yaw = 2.0 * math.atan2(pose.orientation.z, pose.orientation.w)
        ahead = Point(pose.position.x + 0.07 * math.cos(yaw),
                      pose.position.y + 0.07 * math.sin(yaw), 0.025)
        deadline = time.monotonic() + 10.0
        while not prox.messages and time.monotonic() < deadline:
            mover.publish(ahead)
            time.sleep(0.1)
        msg = prox.wait(3)[-1]
        self.assertEqual(msg.detectedObject.data, self.h["probe_box"])
        self.assertTrue(0.0 < msg.detectedPoint.z < 0.05)
        mover.publish(Point(0.8, 0.8, 0.025))
        wait_sim_time(0.3)
        prox.clear()
        wait_sim_time(0.5)
        self.assertEqual(prox.messages, [])
        self.disable_pub(topic)
        self.assertEqual(self.disable_sub(sid).result, 1)

    def test_transforms_on_tf(self):
        # The rename "base%map" applies to every stream's frame ids (the plugin's remapping),
        # so once it is enabled the joint's parent frame is "/base" too.
        renamed = self.publisher("tf_base", GET_TRANSFORM, self.h["ePuck"], WORLD, "base%map")
        child = self.publisher("tf_joint", GET_TRANSFORM, self.h["ePuck_leftJoint"], HANDLE_PARENT)
        tf = Collector("/tf", TFMessage)
        deadline = time.monotonic() + 20.0
        pairs = set()
        while time.monotonic() < deadline and not {("/base", "/ePuck_leftJoint"),
                                                    ("/map", "/base")} <= pairs:
            pairs |= {(t.header.frame_id, t.child_frame_id)
                      for m in list(tf.messages) for t in m.transforms}
            time.sleep(0.05)
        self.assertIn(("/base", "/ePuck_leftJoint"), pairs)
        self.assertIn(("/map", "/base"), pairs)
        for name in (child, renamed):
            self.assertEqual(self.disable_pub(name).referenceCounter, 0)

    def test_signals_through_streams(self):
        topic = self.publisher("int_signal", GET_INTEGER_SIGNAL, 0, 0, "answer")
        values = Collector("/vrep/" + topic, Int32)
        sid = self.subscriber("set_answer", SET_INTEGER_SIGNAL, 0, 0, "answer")
        wait_sim_time(0.3)
        self.assertEqual(values.messages, [])                # absent signal: nothing
        setter = rospy.Publisher("/vrep/set_answer", Int32, queue_size=1)
        deadline = time.monotonic() + 10.0
        while not values.messages and time.monotonic() < deadline:
            setter.publish(Int32(42))
            time.sleep(0.1)
        self.assertEqual(values.wait(2)[-1].data, 42)
        self.assertEqual(self.disable_sub(sid).result, 1)
        self.assertEqual(self.disable_sub(sid).result, 0)
        self.disable_pub(topic)

    def test_set_joint_state_moves_wheels_and_disable_stops_it(self):
        topic = self.publisher("wheels_state", GET_JOINT_STATE, HANDLE_ALL)
        joints = Collector("/vrep/" + topic, JointState)
        sid, pub = self.drive((4.0, 4.0))
        wait_sim_time(0.3)
        joints.clear()
        np.testing.assert_allclose(joints.wait(2)[-1].velocity, [4.0, 4.0], atol=0.05)
        self.assertEqual(self.disable_sub(sid).result, 1)
        msg = JointSetStateData()
        msg.handles.data = [self.h["ePuck_leftJoint"], self.h["ePuck_rightJoint"]]
        msg.setModes.data, msg.values.data = [2, 2], [-1.0, -1.0]
        for _ in range(5):
            pub.publish(msg)
            time.sleep(0.05)
        wait_sim_time(0.3)
        joints.clear()
        np.testing.assert_allclose(joints.wait(2)[-1].velocity, [4.0, 4.0], atol=0.05)  # unchanged
        stop_id, _ = self.drive((0.0, 0.0), "/test_vrep_streams/stop")
        self.disable_sub(stop_id)
        self.disable_pub(topic)

    def test_z_stop_ends_every_stream(self):
        topic = self.publisher("last", GET_JOINT_STATE, self.h["ePuck_rightJoint"])
        self.assertEqual(topic, "last")
        sid = self.subscriber("last_wheels", SET_JOINT_STATE)
        self.assertIn("/vrep/last", vrep_topics()[0])
        self.assertIn("/vrep/last_wheels", vrep_topics()[1])
        self.assertEqual(service("simRosStopSimulation", simRosStopSimulation)().result, 1)
        published, subscribed = vrep_topics()
        self.assertNotIn("/vrep/last", published)
        self.assertNotIn("/vrep/last_wheels", subscribed)
        self.assertEqual(self.disable_pub(topic).referenceCounter, -1)
        self.assertEqual(self.disable_sub(sid).result, 0)
        self.assertEqual(self.publisher("late", GET_JOINT_STATE, HANDLE_ALL), "")
        self.assertEqual(self.subscriber("late_wheels", SET_JOINT_STATE), -1)
        self.assertEqual(service("simRosStartSimulation", simRosStartSimulation)().result, 1)
        self.assertEqual(self.publisher("late", GET_JOINT_STATE, HANDLE_ALL), "late")


if __name__ == "__main__":
    rostest.rosrun(PKG, "vrep_streams_client", VrepStreams)

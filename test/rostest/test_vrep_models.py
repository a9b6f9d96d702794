#!/usr/bin/python3
"""simRosLoadModel, simRosCopyPasteObjects, simRosRemoveModel and simRosRemoveObject against the
running simulator (default arena, ePuck0 and ePuck1 at start): a new robot appears in every face
(handles by name, its topics in the profile under test (~profile), TF, LEDs and markers, camera,
joints, proximity reads), a removed one leaves every face while the others keep going, and bad
requests answer -1 with a reason in simRosGetLastErrors. Every test undoes what it adds, and
derives names from the scene, so the order of the tests does not matter."""
import math

import rospy
import rostest
import vrep_common.srv
from geometry_msgs.msg import PoseStamped, Twist
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, Imu, Range
from std_msgs.msg import UInt8MultiArray
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import MarkerArray
from vrep_common.msg import VrepInfo

from epuck_vrep_compat.compat.vrep_codes import STRMCMD_GET_OBJECT_POSE
from epuck_vrep_compat.ros.epuck.profiles import PROFILES
from epuck_vrep_compat.scene.epuck_model import suffix_number
from sim_test_helpers import (PKG, Collector, SimTestCase, simulator_topics, wait_for_message,
                              wait_sim_time)

HANDLE_ALL, WORLD, ALL_OBJECTS = -2, -1, 109
OBJECTS_PER_ROBOT = 26


def call(name, **fields):
    service = getattr(vrep_common.srv, name)
    return rospy.ServiceProxy("/vrep/" + name, service).call(service._request_class(**fields))


def handle(name):
    return call("simRosGetObjectHandle", objectName=name).handle


def scene_objects():
    """{name: handle} of every object of the scene."""
    data = call("simRosGetObjectGroupData", objectType=ALL_OBJECTS, dataType=0)
    return dict(zip(data.strings, data.handles))


def pose_xy(h):
    p = call("simRosGetObjectPose", handle=h, relativeToObjectHandle=WORLD).pose.pose.position
    return p.x, p.y


class VrepModels(SimTestCase):
    NODE = "test_vrep_models"
    SERVICES = ("/vrep/simRosLoadModel",)
    SERVICE_TIMEOUT_S = 30.0
    FIRST_MESSAGE = ("/clock", Clock)

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.profile = PROFILES[rospy.get_param("~profile", "vrep")]

    def setUp(self):
        self.last_errors()

    def last_errors(self):
        res = call("simRosGetLastErrors")
        return res.errorStrings.split("\0")[:-1] if res.errorStrings else []

    def topic(self, robot, role):
        return self.profile.topic(robot, role)

    def frame(self, robot, frame):
        return self.profile.frame(robot, frame)

    def new_robot_name(self, base_name):
        """The robot a base object ``ePuck#k`` drives: number k + 1 in the profile."""
        return self.profile.robot_name(suffix_number(base_name) + 1)

    def assert_faces_of(self, robot, suffix):
        """Every face of a robot that was just added, with object suffix ``#k``."""
        base = handle("ePuck" + suffix)
        for part in ("ePuck_leftJoint", "ePuck_proxSensor0", "ePuck_camera", "dummy_proxSensor7"):
            self.assertGreater(handle(part + suffix), base, part)
        sensor = handle("ePuck_proxSensor0" + suffix)
        self.assertEqual(call("simRosGetObjectParent", handle=sensor).parentHandle, base)
        self.assertIn(call("simRosReadProximitySensor", handle=sensor).result, (0, 1))
        joints = call("simRosGetJointState", handle=HANDLE_ALL).state.name
        self.assertIn("ePuck_rightJoint" + suffix, joints)
        image = call("simRosGetVisionSensorImage", handle=handle("ePuck_camera" + suffix))
        self.assertEqual(image.result, 1)
        rng = wait_for_message(self.topic(robot, "proximity0"), Range)
        self.assertEqual(rng.header.frame_id, self.frame(robot, "base_prox0"))
        imu = wait_for_message(self.topic(robot, self.profile.imu_role or "imu"), Imu)
        self.assertEqual(imu.header.frame_id, self.frame(robot, "base_link"))
        self.assertEqual(wait_for_message(self.topic(robot, "camera"), Image).width, 40)
        info = wait_for_message(self.topic(robot, "camera_info"), CameraInfo)
        self.assertEqual(info.header.frame_id, self.frame(robot, "camera_optical"))
        self.assertEqual(len(wait_for_message(self.topic(robot, "led_state"),
                                              UInt8MultiArray).data), 10)
        if self.profile.publishes_odometry:
            wait_for_message(self.topic(robot, "odom"), rospy.AnyMsg)
            wait_for_message(self.topic(robot, "scan"), rospy.AnyMsg)
        base_frame = self.frame(robot, "base_link")
        self.wait_until(lambda: any(t.child_frame_id == base_frame for t in
                                    wait_for_message("/tf", TFMessage).transforms), "TF")
        self.wait_until(lambda: any(m.ns == robot for m in
                                    wait_for_message("/vrep/markers", MarkerArray).markers),
                        "markers")
        published, subscribed, _ = simulator_topics()
        self.assertIn(self.topic(robot, "proximity7"), published)
        self.assertIn(self.topic(robot, "cmd_vel"), subscribed)

    def wait_until(self, condition, what, tries=60):
        for _ in range(tries):
            if condition():
                return
        self.fail(f"{what}: never seen")

    def remove(self, base_handle):
        self.assertEqual(call("simRosRemoveModel", handle=base_handle).result, OBJECTS_PER_ROBOT)

    # --- loading ----------------------------------------------------------------------------
    def test_a_loaded_model_appears_in_every_face_and_drives(self):
        before = scene_objects()
        largest = max(suffix_number(n) for n in before)
        res = call("simRosLoadModel", fileName="models/robots/mobile/e-puck.ttm")
        self.assertGreater(res.baseHandle, max(before.values()))          # new handles
        self.assertEqual(res.result, res.baseHandle)
        suffix = f"#{largest + 1}"
        self.assertEqual(handle("ePuck" + suffix), res.baseHandle)
        robot = self.new_robot_name("ePuck" + suffix)
        self.assert_faces_of(robot, suffix)
        self.assertEqual({n: h for n, h in scene_objects().items() if n in before}, before)
        start = pose_xy(res.baseHandle)
        cmd = rospy.Publisher(self.topic(robot, "cmd_vel"), Twist, queue_size=1)
        for _ in range(30):
            cmd.publish(Twist())          # zero first: the connection is up before it matters
            if cmd.get_num_connections():
                break
            rospy.sleep(0.1)
        for _ in range(20):
            msg = Twist()
            msg.angular.z = 2.0
            cmd.publish(msg)
            wait_sim_time(0.05)
        cmd.unregister()
        end = call("simRosGetObjectPose", handle=res.baseHandle, relativeToObjectHandle=WORLD)
        turned = 2.0 * math.atan2(end.pose.pose.orientation.z, end.pose.pose.orientation.w)
        self.assertGreater(abs(turned), 0.3, (start, end.pose.pose))
        self.remove(res.baseHandle)
        self.assertEqual(self.last_errors(), [])

    # --- copy and paste ---------------------------------------------------------------------
    def test_copy_paste_of_a_robot_base_pastes_a_robot_beside_it(self):
        original = handle("ePuck")
        largest = max(suffix_number(n) for n in scene_objects())
        res = call("simRosCopyPasteObjects", objectHandles=[original])
        self.assertEqual(res.result, 1)
        self.assertEqual(len(res.newObjectHandles), OBJECTS_PER_ROBOT)
        suffix = f"#{largest + 1}"
        self.assertEqual(res.newObjectHandles[0], handle("ePuck" + suffix))
        (x0, y0), (x1, y1) = pose_xy(original), pose_xy(res.newObjectHandles[0])
        self.assertLess(math.hypot(x1 - x0, y1 - y0), 0.25)
        self.assertGreaterEqual(math.hypot(x1 - x0, y1 - y0), 2 * 0.037)
        self.assert_faces_of(self.new_robot_name("ePuck" + suffix), suffix)
        self.remove(res.newObjectHandles[0])
        sensor = handle("ePuck_proxSensor2")
        refused = call("simRosCopyPasteObjects", objectHandles=[original, sensor])
        self.assertEqual((refused.result, list(refused.newObjectHandles)), (-1, []))
        errors = self.last_errors()
        self.assertEqual(len(errors), 1)
        self.assertIn("only whole robots can be copied", errors[0])

    # --- removing ---------------------------------------------------------------------------
    def test_a_removed_robot_leaves_every_face_and_the_others_go_on(self):
        parts = {n: h for n, h in scene_objects().items() if n.endswith("#0")}
        others = {n: h for n, h in scene_objects().items() if n not in parts}
        self.assertEqual(len(parts), OBJECTS_PER_ROBOT)
        gone, stays = self.profile.robot_name(1), self.profile.robot_name(0)
        self.assertEqual(call("simRosEnablePublisher", topicName="gone_pose", queueSize=1,
                              streamCmd=STRMCMD_GET_OBJECT_POSE, auxInt1=parts["ePuck#0"],
                              auxInt2=WORLD).effectiveTopicName, "gone_pose")
        watched = {t: Collector(t, m) for t, m in (
            (self.topic(gone, "proximity0"), Range), (self.topic(stays, "proximity0"), Range),
            ("/vrep/gone_pose", PoseStamped), ("/tf", TFMessage))}
        info = Collector("/vrep/info", VrepInfo)
        for collector in watched.values():
            collector.wait(1, timeout_s=20)
        self.remove(parts["ePuck#0"])
        for name in parts:
            self.assertEqual(handle(name), -1, name)
        errors = self.last_errors()         # read now: the log keeps only the last 50
        self.assertEqual(scene_objects(), others)        # nothing renumbered, nothing else gone
        camera = parts["ePuck_camera#0"]
        self.assertEqual(call("simRosGetObjectParent", handle=camera).parentHandle, -1)
        wait_sim_time(0.3)                  # what was under way before the removal arrives
        for collector in list(watched.values()) + [info]:
            collector.clear()
        wait_sim_time(1.0)
        self.assertEqual(watched[self.topic(gone, "proximity0")].messages, [])
        self.assertEqual(watched["/vrep/gone_pose"].messages, [])       # the stream ended
        self.assertGreaterEqual(len(watched[self.topic(stays, "proximity0")].messages), 10)
        self.assertGreaterEqual(len(info.messages), 10)                  # still stepping
        frames = {t.child_frame_id for m in watched["/tf"].messages for t in m.transforms}
        self.assertIn(self.frame(stays, "base_link"), frames)
        self.assertNotIn(self.frame(gone, "base_link"), frames)
        published, subscribed, _ = simulator_topics()
        self.assertNotIn(self.topic(gone, "proximity0"), published)
        self.assertNotIn(self.topic(gone, "camera"), published)
        self.assertNotIn(self.topic(gone, "cmd_vel"), subscribed)
        self.assertNotIn("/vrep/gone_pose", published)
        errors += self.last_errors()
        self.assertTrue(any("get_object_pose" in e and "ended" in e for e in errors), errors)
        for collector in list(watched.values()) + [info]:
            collector.unregister()
        again = call("simRosLoadModel", fileName="ePuck.ttm").baseHandle   # a new robot there
        self.assertGreater(again, max(others.values()))
        self.assertNotIn(again, parts.values())
        self.remove(again)

    def test_a_removed_obstacle_leaves_the_collision_world(self):
        cylinder = handle("cylinder0")
        robot = handle("ePuck")
        pose = vrep_common.srv.simRosSetObjectPoseRequest().pose
        pose.position.x, pose.position.y, pose.orientation.w = 0.25 - 0.04 - 0.037 - 0.015, \
            -0.30, 1.0
        self.assertEqual(call("simRosSetObjectPose", handle=robot, relativeToObjectHandle=WORLD,
                              pose=pose).result, 1)
        front = [handle("ePuck_proxSensor0"), handle("ePuck_proxSensor7")]
        wait_sim_time(0.2)
        seen = [call("simRosReadProximitySensor", handle=h).detectedObject for h in front]
        self.assertIn(cylinder, seen)
        self.assertEqual(call("simRosRemoveObject", handle=cylinder).result, 1)
        wait_sim_time(0.2)
        seen = [call("simRosReadProximitySensor", handle=h) for h in front]
        self.assertEqual([(s.result, s.detectedObject) for s in seen], [(0, -1)] * 2)
        self.assertEqual(self.last_errors(), [])
        self.assertEqual(handle("cylinder0"), -1)
        self.assertEqual(self.last_errors(), ["simRosGetObjectHandle: object 'cylinder0' does "
                                              "not exist"])

    # --- bad requests -----------------------------------------------------------------------
    def test_bad_requests_answer_minus_one_with_a_reason_and_change_nothing(self):
        before = scene_objects()
        seq = rospy.wait_for_message("/vrep/info", VrepInfo, timeout=10).headerInfo.seq
        self.assertEqual(call("simRosLoadModel", fileName="bubbleRob.ttm").baseHandle, -1)
        self.assertEqual(call("simRosLoadModel", fileName="").result, -1)
        self.assertEqual(call("simRosRemoveModel", handle=99999).result, -1)
        self.assertEqual(call("simRosRemoveObject", handle=0).result, -1)
        self.assertEqual(call("simRosRemoveObject", handle=handle("ePuck_leftWheel")).result, -1)
        self.assertEqual(call("simRosRemoveModel", handle=handle("dummy_proxSensor4")).result, -1)
        self.assertEqual(call("simRosCopyPasteObjects", objectHandles=[123456]).result, -1)
        self.assertEqual(call("simRosCopyPasteObjects", objectHandles=[handle("Wall0")]).result,
                         -1)
        errors = self.last_errors()
        self.assertEqual(len(errors), 8, errors)
        unknown = [e for e in errors if e.startswith(
            "simRosLoadModel: model file 'bubbleRob.ttm' is not known (models: ")]
        self.assertEqual(len(unknown), 1, errors)       # the list names every model file
        self.assertIn("ePuck.ttm, e-puck.ttm", unknown[0])
        self.assertIn("ABB IRB 140.ttm", unknown[0])
        self.assertIn("simRosRemoveModel: object handle 99999 does not exist", errors)
        self.assertTrue(any("is part of robot" in e and "'ePuck' instead" in e for e in errors))
        self.assertTrue(any("is a static scene object" in e for e in errors))
        self.assertEqual(scene_objects(), before)
        later = rospy.wait_for_message("/vrep/info", VrepInfo, timeout=10).headerInfo.seq
        self.assertGreater(later, seq)                                   # still running
        self.assertEqual([e for e in self.guard.errors if "/vrep" in e], [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "vrep_models", VrepModels)

#!/usr/bin/python3
"""A /vrep client loads an IRB 140 by V-REP's model file name: it is named as V-REP names a
copy, answers the joint services, publishes its joint states (/IRB140_0/...), appears in TF and
in group data, takes a speed scale; simRosRemoveModel removes it and its topics; the thesis's
[/robot] HUB, given the copy's names, publishes its handles."""
import time

import rospy
import rosgraph.masterapi
import rostest
import tf2_ros
from sensor_msgs.msg import JointState

from epuck_vrep_compat.msg import IrbMsg

from sim_test_helpers import SimTestCase, call, handle, wait_sim_time

WORLD = -1
JOINT_TYPE = 1           # sim_object_joint_type


def publishers_of(topic):
    master = rosgraph.masterapi.Master(rospy.get_name())
    return [n for t, nodes in master.getSystemState()[0] if t == topic for n in nodes]


class CellModels(SimTestCase):
    NODE = "test_cell_models"
    SERVICES = ("/vrep/simRosLoadModel",)
    SIM_TIME_S = 0.5

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.tf = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.tf)

    def test_1_load_use_and_remove_an_irb140(self):
        res = call("simRosLoadModel", fileName="models/robots/non-mobile/ABB IRB 140.ttm")
        self.assertGreater(res.result, 0)
        base = res.baseHandle
        self.assertEqual(handle("IRB140#0"), base)
        joint = handle("IRB140_joint2#0")
        self.assertGreater(joint, 0)
        self.assertEqual(call("simRosSetJointTargetPosition", handle=joint,
                              targetPosition=0.4).result, 1)
        msg = rospy.wait_for_message("/IRB140_0/joint_states", JointState, timeout=30)
        self.assertEqual(len(msg.name), 6)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            state = call("simRosGetJointState", handle=joint)
            if abs(state.state.position[0] - 0.4) < 5e-3:
                break
            wait_sim_time(0.1)
        self.assertAlmostEqual(state.state.position[0], 0.4, delta=5e-3)
        t = self.tf.lookup_transform("world", "IRB140_link6#0", rospy.Time(0),
                                     rospy.Duration(10))
        self.assertTrue(abs(t.transform.translation.z) < 2.0)
        joints = call("simRosGetObjectGroupData", objectType=JOINT_TYPE, dataType=0)
        self.assertIn("IRB140_joint6#0", joints.strings)
        self.assertTrue(rospy.has_param("/IRB140_0/robot_description"))
        self.assertGreater(call("simRosRemoveModel", handle=base).result, 1)   # objects removed
        self.assertEqual(handle("IRB140#0"), -1)
        deadline = time.monotonic() + 20
        while publishers_of("/IRB140_0/joint_states") and time.monotonic() < deadline:
            time.sleep(0.2)
        self.assertEqual(publishers_of("/IRB140_0/joint_states"), [])
        self.assertFalse(rospy.has_param("/IRB140_0/robot_description"))

    def test_2_youbot_and_six_by_their_names(self):
        for file_name, base in (("KUKA YouBot.ttm", "youBot#0"),
                                ("comau_smart_six.urdf", "SIX#0")):
            res = call("simRosLoadModel", fileName=file_name)
            self.assertGreater(res.result, 0, file_name)
            self.assertEqual(handle(base), res.baseHandle)
            self.assertGreater(call("simRosRemoveModel", handle=res.baseHandle).result, 1)
        self.assertEqual(call("simRosLoadModel", fileName="no_such_robot.ttm").result, -1)

    def test_3_the_hub_finds_a_loaded_irb140_by_the_names_given(self):
        # cell_models.test starts [/robot] with ~irb_robot IRB140#0 and the copy's six joints
        res = call("simRosLoadModel", fileName="ABB IRB 140.ttm")
        self.assertGreater(res.result, 0)
        expected = [handle(f"IRB140_joint{k}#0") for k in range(1, 7)]
        self.assertNotIn(-1, expected)
        latest = []
        sub = rospy.Subscriber("/IrbHandles", IrbMsg, latest.append, queue_size=10)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and not (
                latest and latest[-1].hIrbRobot == res.baseHandle
                and list(latest[-1].hIrbJoint) == expected):
            time.sleep(0.1)
        sub.unregister()
        self.assertTrue(latest, "no /IrbHandles from [/robot]")
        self.assertEqual((latest[-1].hIrbRobot, list(latest[-1].hIrbJoint)),
                         (res.baseHandle, expected))
        self.assertGreater(call("simRosRemoveModel", handle=res.baseHandle).result, 1)

    def test_9_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun("epuck_vrep_compat", "test_cell_models", CellModels)

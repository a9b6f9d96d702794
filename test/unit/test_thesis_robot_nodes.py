"""The robot subset's logic (no master): the HUB's handle messages, the joint names, the
joint poses from group data 9/10."""
import rospy
from std_msgs.msg import Header

from epuck_vrep_compat.compat.thesis_names import COMAU, IRB, YOUBOT
from epuck_vrep_compat.msg import ComauMsg, YouBotMsg, vett_posOrAssGiunto, vett_posOrRelGiunto
from epuck_vrep_compat.thesis.hub import handles_message, joint_handles_of, look_up
from epuck_vrep_compat.thesis.joint_names import joint_handles_message
from epuck_vrep_compat.thesis.joint_poses import parent_frames, poses_by_handle, poses_message


def test_topic_and_node_names_are_the_theses():
    assert COMAU.handles_topic == "/ComauHandles" and COMAU.joint_handles_topic == \
        "/Comau_JointHandles"
    assert IRB.poses_topic(True) == "/Irb_PosOrAss" and YOUBOT.poses_topic(False) == \
        "/YouBot_PosOrRel"
    assert COMAU.poses_node(True) == "NComau_PosOrAss" and IRB.poses_node(False) == \
        "NIrb_PosOrRel"


def test_missing_names_get_minus_one_and_a_failed_call_gives_nothing():
    scene = {"SIX": 1, **{f"SIX_joint{i}": 10 + i for i in range(1, 7)}}
    handles = look_up(lambda name: scene.get(name, -1), ("SIX",) + COMAU.joint_names)
    assert handles == (1, 11, 12, 13, 14, 15, 16, -1)
    msg = handles_message(ComauMsg, handles)
    assert msg.hComauRobot == 1 and list(msg.hComauJoint) == [11, 12, 13, 14, 15, 16, -1]
    assert joint_handles_of(msg) == [11, 12, 13, 14, 15, 16, -1]
    assert look_up(lambda name: None if name == "SIX_joint3" else 1, COMAU.joint_names) is None


def test_youbot_message_holds_sixteen_joints():
    msg = handles_message(YouBotMsg, list(range(17)))
    assert msg.hYouBotRobot == 0 and len(msg.hYouBotJoint) == 16


def test_joint_handles_carry_index_handle_and_name():
    msg = joint_handles_message([11, -1, 99], {11: "SIX_joint1", 5: "other"})
    assert [(j.indice, j.handle, j.nome) for j in msg.handles] == [
        (0, 11, "SIX_joint1"), (1, -1, ""), (2, 99, "")]


def test_group_pose_data_is_split_per_object():
    poses = poses_by_handle([4, 7], [1, 2, 3, 0.1, 0.2, 0.3, 4, 5, 6, 0.4, 0.5, 0.6])
    assert list(poses[7]) == [4, 5, 6, 0.4, 0.5, 0.6]
    assert poses_by_handle([4, 7], [1, 2, 3]) == {}          # arrays that do not fit


def test_parents_name_the_relative_frame():
    frames = parent_frames([1, 2, 3], [-1, 1, 42], {1: "SIX", 2: "SIX_joint1"})
    assert frames == {1: "world", 2: "SIX", 3: "world"}


def test_absolute_and_relative_messages():
    joints = [(0, 11, "SIX_joint1"), (1, 12, "SIX_joint2"), (2, 13, "SIX_joint3")]
    poses = {11: [0.1, 0.2, 0.3, 1.5707, 1.3294, 1.5708], 13: [1, 2, 3, 0, 0, 0]}
    stamp = rospy.Time(12, 500)
    msg, missing = poses_message(joints, poses, stamp, True, {})
    assert isinstance(msg, vett_posOrAssGiunto) and missing == [12]
    first = msg.posizioneOrientamento[0]
    assert first.headerGiunto.header == Header(stamp=stamp, frame_id="world")
    assert (first.headerGiunto.indice, first.headerGiunto.handle, first.headerGiunto.nome) == (
        0, 11, "SIX_joint1")
    assert list(first.Posizione_Assoluta) == [0.1, 0.2, 0.3]
    assert list(first.Orientamento_Assoluto) == [1.5707, 1.3294, 1.5708]
    assert msg.posizioneOrientamento[1].headerGiunto.indice == 2
    rel, _ = poses_message(joints, poses, stamp, False, {11: "SIX", 13: "SIX_joint2"})
    assert isinstance(rel, vett_posOrRelGiunto)
    assert [e.headerGiunto.header.frame_id for e in rel.posizioneOrientamento] == [
        "SIX", "SIX_joint2"]
    assert list(rel.posizioneOrientamento[1].Posizione_Relativa) == [1, 2, 3]

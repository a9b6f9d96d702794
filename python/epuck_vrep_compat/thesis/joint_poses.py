"""[/N<Robot>_PosOrAss] and [/N<Robot>_PosOrRel] (thesis section 4.2.2): every joint's position
and orientation, absolute (relative to the world) or relative to its parent object.

Each node takes the joints from /<Robot>_JointHandles and, every cycle, reads the poses of all
joints of the scene with ONE simRosGetObjectGroupData call (object type joint, data type 9:
absolute position + Euler angles, or 10: the same relative to the parent), then keeps its
robot's joints. One call gives one consistent snapshot of the scene for the whole message and
costs the simulator one request per cycle instead of one per joint (the alternative,
simRosGetObjectPose per joint, would be 29 requests per cycle and node in the cell). It needs
V-REP 3.2.1's group data, which returns every object of the group, as the thesis's proxSensors
and this simulator do. Orientations are V-REP's Euler angles (alpha, beta, gamma),
R = Rx(alpha) Ry(beta) Rz(gamma), as simGetObjectOrientation reports them
(:func:`epuck_vrep_compat.geometry.transforms.vrep_euler_angles`).

headerGiunto: stamp = ROS time of the reading (simulation time under /use_sim_time),
frame_id = "world" (absolute) or the parent's object name (relative), indice/handle/nome from
JointHandles. Joints with handle -1 are left out of the message.

Parameters: ``~rate`` (20 Hz).
"""
import threading
from typing import Dict, List, Sequence, Tuple

import rospy
from std_msgs.msg import Header
from vrep_common.srv import simRosGetObjectGroupData

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.frames import WORLD_FRAME
from epuck_vrep_compat.compat.thesis_names import ROBOTS
from epuck_vrep_compat.msg import (
    headerGiunto, posOrAssGiunto, posOrRelGiunto, vett_JointHandles, vett_posOrAssGiunto,
    vett_posOrRelGiunto)
from epuck_vrep_compat.thesis import params
from epuck_vrep_compat.thesis.vrep_client import VrepClient, run_node, spin_periodic

POSE_FLOATS = 6                 # data types 9/10: x, y, z, alpha, beta, gamma per object
Joint = Tuple[int, int, str]    # (indice, handle, nome)


def poses_by_handle(handles: Sequence[int], floats: Sequence[float]) -> Dict[int, Sequence[float]]:
    """{handle: (x, y, z, alpha, beta, gamma)} of a group data 9/10 answer."""
    if len(floats) != POSE_FLOATS * len(handles):
        return {}
    return {h: floats[POSE_FLOATS * k:POSE_FLOATS * (k + 1)] for k, h in enumerate(handles)}


def parent_frames(handles: Sequence[int], parents: Sequence[int],
                  names: Dict[int, str]) -> Dict[int, str]:
    """{handle: its parent's name, or "world" for an object without parent} from group data 2
    (parents) and 0 (names) of all objects."""
    return {h: WORLD_FRAME if p < 0 else names.get(p, WORLD_FRAME)
            for h, p in zip(handles, parents)}


def poses_message(joints: Sequence[Joint], poses: Dict[int, Sequence[float]], stamp,
                  absolute: bool, frames: Dict[int, str]):
    """vett_posOrAssGiunto (absolute) or vett_posOrRelGiunto of the joints that have a pose,
    each with its frame from ``frames`` ("world" if absent), and the handles of the joints
    that have no pose."""
    vector_class, element_class = ((vett_posOrAssGiunto, posOrAssGiunto) if absolute
                                   else (vett_posOrRelGiunto, posOrRelGiunto))
    elements, missing = [], []
    for indice, handle, nome in joints:
        pose = poses.get(handle)
        if pose is None:
            missing.append(handle)
            continue
        frame_id = frames.get(handle, WORLD_FRAME)
        header = headerGiunto(header=Header(stamp=stamp, frame_id=frame_id), indice=indice,
                              handle=handle, nome=nome)
        elements.append(element_class(header, list(pose[:3]), list(pose[3:])))
    return vector_class(posizioneOrientamento=elements), missing


class JointPoses:
    """One robot's pose node: its joints' poses, absolute or relative, every cycle."""

    def __init__(self, label: str, absolute: bool):
        self.robot = ROBOTS[label]
        self.absolute = absolute
        self.rate_hz = params.read_rate_hz()
        self.client = VrepClient({"simRosGetObjectGroupData": simRosGetObjectGroupData})
        self._data_type = vc.GROUP_DATA_ABS_POSE_EULER if absolute else vc.GROUP_DATA_REL_POSE_EULER
        topic = self.robot.poses_topic(absolute)
        # 10 messages = 0.5 s at 20 Hz for a slow subscriber (rosbag), never blocking the loop
        self._pub = rospy.Publisher(topic, vett_posOrAssGiunto if absolute else vett_posOrRelGiunto,
                                    queue_size=10)
        self._lock = threading.Lock()
        self._joints: List[Joint] = []
        self._frames: Dict[int, str] = {}       # relative: {joint handle: parent's name}
        self._frames_pending = False
        rospy.loginfo("%s: %s -> %s (group data type %d), rate %.1f Hz", rospy.get_name(),
                      self.robot.joint_handles_topic, topic, self._data_type, self.rate_hz)

    def _on_joint_handles(self, msg: vett_JointHandles):
        joints = [(j.indice, j.handle, j.nome) for j in msg.handles if j.handle >= 0]
        if len(joints) < len(msg.handles):
            rospy.logwarn("%s: %d joints of %s have no handle (-1): left out", rospy.get_name(),
                          len(msg.handles) - len(joints), self.robot.joint_handles_topic)
        with self._lock:
            self._joints = joints
            self._frames_pending = not self.absolute

    def _look_up_frames(self) -> bool:
        parents = self.client.group_data(vc.APPOBJ_OBJECT, vc.GROUP_DATA_PARENTS)
        names = self.client.object_names() if parents is not None else None
        if names is None:
            return False
        self._frames = parent_frames(parents.handles, parents.intData, names)
        return True

    def step(self):
        with self._lock:
            joints, frames_pending, self._frames_pending = self._joints, self._frames_pending, False
        if frames_pending and not self._look_up_frames():
            with self._lock:
                self._frames_pending = True
            return
        if not joints:
            return
        res = self.client.group_data(vc.OBJECT_JOINT, self._data_type)
        if res is None:
            return
        msg, missing = poses_message(joints, poses_by_handle(res.handles, res.floatData),
                                     rospy.get_rostime(), self.absolute, self._frames)
        if missing:
            self.client.log.warn("missing", "%s: no pose for handles %s (not joints of the scene)",
                                 rospy.get_name(), missing)
        self._pub.publish(msg)

    def run(self):
        rospy.Subscriber(self.robot.joint_handles_topic, vett_JointHandles,
                         self._on_joint_handles, queue_size=1)
        spin_periodic(self.rate_hz, self.step)


def main(label: str, absolute: bool) -> int:
    return run_node(ROBOTS[label].poses_node(absolute), lambda: JointPoses(label, absolute))

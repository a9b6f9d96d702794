"""[/Comau], [/Irb], [/YouBot] (thesis section 4.2.1): the names of a robot's joints.

Each takes the joint handles from [/robot]'s /<Robot>Handles, gets every object's name with
one simRosGetObjectGroupData call (all objects, data type 0: names), as the thesis does, and
publishes a latched vett_JointHandles on /<Robot>_JointHandles: one JointHandles per joint,
``indice`` = its index in the handles message's joint array (0-based), ``handle``, ``nome``
("" for a handle of -1 or one the scene does not know).

Parameters: ``~rate`` (20 Hz): how often a pending lookup is tried while it fails.
"""
import threading
from typing import Dict, List, Optional, Sequence

import rospy
from vrep_common.srv import simRosGetObjectGroupData

from epuck_vrep_compat.compat.thesis_names import ROBOTS
from epuck_vrep_compat.msg import JointHandles, vett_JointHandles
from epuck_vrep_compat.thesis import params
from epuck_vrep_compat.thesis.hub import HANDLES_MESSAGES, joint_handles_of
from epuck_vrep_compat.thesis.vrep_client import VrepClient, run_node, spin_periodic


def joint_handles_message(handles: Sequence[int], names: Dict[int, str]) -> vett_JointHandles:
    return vett_JointHandles(handles=[
        JointHandles(indice=i, handle=h, nome=names.get(h, "") if h >= 0 else "")
        for i, h in enumerate(handles)])


class JointNames:
    """One robot's joint-name node: its joints' handles from the HUB, named, latched."""

    def __init__(self, label: str):
        self.robot = ROBOTS[label]
        self.rate_hz = params.read_rate_hz()
        self.client = VrepClient({"simRosGetObjectGroupData": simRosGetObjectGroupData})
        self._pub = rospy.Publisher(self.robot.joint_handles_topic, vett_JointHandles,
                                    queue_size=1, latch=True)
        self._lock = threading.Lock()
        self._pending: Optional[List[int]] = None
        rospy.loginfo("%s: %s -> %s, rate %.1f Hz", rospy.get_name(), self.robot.handles_topic,
                      self.robot.joint_handles_topic, self.rate_hz)

    def _on_handles(self, msg):
        with self._lock:
            self._pending = joint_handles_of(msg)

    def step(self):
        with self._lock:
            handles, self._pending = self._pending, None
        if handles is None:
            return
        names = self.client.object_names()
        if names is None:
            with self._lock:                # failed (warned): try again, unless newer arrived
                self._pending = self._pending if self._pending is not None else handles
            return
        unknown = [h for h in handles if h >= 0 and h not in names]
        if unknown:
            self.client.log.warn("unknown", "%s: the scene has no objects with handles %s",
                                 rospy.get_name(), unknown)
        self._pub.publish(joint_handles_message(handles, names))

    def run(self):
        rospy.Subscriber(self.robot.handles_topic, HANDLES_MESSAGES[self.robot.label],
                         self._on_handles, queue_size=1)
        spin_periodic(self.rate_hz, self.step)


def main(label: str) -> int:
    return run_node(label, lambda: JointNames(label))

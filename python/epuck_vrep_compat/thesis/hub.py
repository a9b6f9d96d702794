"""[/robot], the thesis's HUB (section 4.2.1): the handles of the three robots and of their
joints, looked up by name with simRosGetObjectHandle, on /ComauHandles (ComauMsg),
/IrbHandles (IrbMsg) and /YouBotHandles (YouBotMsg), latched.

A name the scene does not have gets V-REP's -1 in its slot and one warning naming the object.
The names are looked up again every ``~refresh_period_s`` (a simulator restarted with another
scene); a message is published again only when a handle changed.

Parameters: ``~<robot>_robot`` and ``~<robot>_joints`` for robot in comau, irb, youbot
(defaults in :mod:`epuck_vrep_compat.compat.thesis_names`), ``~refresh_period_s`` (2.0).
"""
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import rospy
from vrep_common.srv import simRosGetObjectHandle

from epuck_vrep_compat.compat.thesis_names import HUB_NODE, ROBOTS
from epuck_vrep_compat.msg import ComauMsg, IrbMsg, YouBotMsg
from epuck_vrep_compat.thesis import params
from epuck_vrep_compat.thesis.vrep_client import VrepClient, run_node, spin_periodic

HANDLES_MESSAGES = {"Comau": ComauMsg, "Irb": IrbMsg, "YouBot": YouBotMsg}
DEFAULT_REFRESH_PERIOD_S = 2.0


def handles_message(msg_class, handles: Sequence[int]):
    """The robot's handle first, then its joints' (ComauMsg(hComauRobot, hComauJoint), ...)."""
    return msg_class(handles[0], list(handles[1:]))


def joint_handles_of(msg) -> List[int]:
    """The joint handles of a ComauMsg, IrbMsg or YouBotMsg (its second field)."""
    return list(getattr(msg, msg.__slots__[1]))


def look_up(get_handle: Callable[[str], Optional[int]],
            names: Sequence[str]) -> Optional[Tuple[int, ...]]:
    """Handles of ``names`` (-1 for a missing object); None if any call failed."""
    handles = tuple(get_handle(name) for name in names)
    return None if None in handles else handles


class Hub:
    """The HUB node: the robots' and joints' handles, looked up by name, latched."""

    def __init__(self):
        self.names: Dict[str, Tuple[str, ...]] = {}
        for label, robot in ROBOTS.items():
            prefix = robot.param_prefix
            self.names[label] = ((params.read_name(prefix + "_robot", robot.robot_name),)
                                 + params.read_names(prefix + "_joints", robot.joint_names))
        self.refresh_period_s = params.read_float("refresh_period_s", DEFAULT_REFRESH_PERIOD_S)
        self.client = VrepClient({"simRosGetObjectHandle": simRosGetObjectHandle})
        self._publishers = {label: rospy.Publisher(robot.handles_topic, HANDLES_MESSAGES[label],
                                                   queue_size=1, latch=True)
                            for label, robot in ROBOTS.items()}
        self._published: Dict[str, Tuple[int, ...]] = {}
        rospy.loginfo("%s: %s; names looked up every %.1f s", rospy.get_name(), "; ".join(
            f"{label} {names[0]} + {len(names) - 1} joints" for label, names in self.names.items()),
            self.refresh_period_s)

    def _get_handle(self, name: str) -> Optional[int]:
        res = self.client.call("simRosGetObjectHandle", objectName=name)
        return None if res is None else res.handle

    def refresh(self):
        found = {}
        for label, names in self.names.items():
            handles = look_up(self._get_handle, names)
            if handles is None:
                return                  # a failed call (warned): try again next period
            found[label] = handles
        for label, handles in found.items():
            if handles == self._published.get(label):
                continue
            topic = ROBOTS[label].handles_topic
            self._publishers[label].publish(handles_message(HANDLES_MESSAGES[label], handles))
            self._published[label] = handles
            rospy.loginfo("%s: %s: %s", rospy.get_name(), topic, list(handles))
            missing = [name for name, handle in zip(self.names[label], handles) if handle < 0]
            if missing:
                rospy.logwarn("%s: the scene has no object named %s: handle -1 in %s",
                              rospy.get_name(), ", ".join(f"'{n}'" for n in missing), topic)

    def run(self):
        spin_periodic(1.0 / self.refresh_period_s, self.refresh)


def main() -> int:
    return run_node(HUB_NODE, Hub)

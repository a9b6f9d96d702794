"""The cell's robots as V-REP names them: base object and movable joints, defined once.

models/README.md explains each joint. ``joints`` is the contract order (the order of V-REP's
handles and of our joint-state messages). pybullet numbers the same joints in URDF tree order
(:attr:`epuck_vrep_compat.geometry.urdf_kinematics.Chain.joint_names`), which for the youBot
differs: each roller joint sits on its wheel. Address joints by name.
"""
from dataclasses import dataclass
from typing import Tuple


@dataclass(frozen=True)
class RobotNames:
    """A cell robot's V-REP names: its base object and its joints in contract order."""
    base_link: str
    joints: Tuple[str, ...]


IRB140 = RobotNames("IRB140", tuple(f"IRB140_joint{k}" for k in range(1, 7)))
COMAU_SMART_SIX = RobotNames("SIX", tuple(f"SIX_joint{k}" for k in range(1, 8)))
YOUBOT_WHEELS = ("fl", "rl", "rr", "fr")
YOUBOT = RobotNames(
    "youBot",
    tuple(f"youBotArmJoint{k}" for k in range(5))
    + ("youBotGripperJoint1", "youBotGripperJoint2")
    + tuple(f"rollingJoint_{w}" for w in YOUBOT_WHEELS)
    + tuple(f"rollerJoint_{w}" for w in YOUBOT_WHEELS)
    + ("youBotGripperPinionJoint",))


def ros_robot_name(name: str) -> str:
    """A robot's name in ROS names (topics, parameters): V-REP names a copy ``IRB140#0``, and
    ``#`` is not allowed in a ROS name, so the copy's topics are ``/IRB140_0/...``."""
    return name.replace("#", "_")

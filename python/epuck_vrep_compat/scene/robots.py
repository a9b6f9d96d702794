"""The cell's robot models: URDF file, base link and movable joints, named as in V-REP.

The one table of these names; models/README.md explains each joint. ``joints`` is the contract
order (the order of V-REP's handles and of our joint-state messages). pybullet numbers the same
joints in URDF tree order (:attr:`kinematics.Chain.joint_names`), which for the youBot differs:
each roller joint sits on its wheel. Address joints by name.
"""
from dataclasses import dataclass
from pathlib import Path

from epuck_vrep_compat.paths import data_path


@dataclass(frozen=True)
class RobotModel:
    """A cell robot's model: URDF file, base link, joints in contract order."""
    urdf_file: str
    base_link: str
    joints: tuple
    fixed_base: bool     # the arms stand on the floor; the youBot's base is floating

    @property
    def urdf_path(self):
        return Path(data_path("models", self.urdf_file))


IRB140 = RobotModel(
    "irb140.urdf", "IRB140", tuple(f"IRB140_joint{k}" for k in range(1, 7)), fixed_base=True)

COMAU_SMART_SIX = RobotModel(
    "comau_smart_six.urdf", "SIX", tuple(f"SIX_joint{k}" for k in range(1, 8)), fixed_base=True)

YOUBOT_WHEELS = ("fl", "rl", "rr", "fr")
YOUBOT = RobotModel(
    "youbot.urdf", "youBot",
    tuple(f"youBotArmJoint{k}" for k in range(5))
    + ("youBotGripperJoint1", "youBotGripperJoint2")
    + tuple(f"rollingJoint_{w}" for w in YOUBOT_WHEELS)
    + tuple(f"rollerJoint_{w}" for w in YOUBOT_WHEELS)
    + ("youBotGripperPinionJoint",),
    fixed_base=False)

CELL_ROBOTS = (IRB140, COMAU_SMART_SIX, YOUBOT)

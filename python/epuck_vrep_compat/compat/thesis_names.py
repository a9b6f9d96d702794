"""Every name the thesis's nodes use, defined once: V-REP object names of the cell (the
defaults of the nodes' private parameters), node names and topics.

The object names are the V-REP-style names of the cell we build, from the robots' own table
(:mod:`.cell_names`). The youBot's 16 joints are in the order of the thesis's
``YouBotMsg``: arm, gripper fingers, the four wheel motors, the four passive mecanum roller
joints, and the gripper's drive pinion (models/README.md says why).
"""
from dataclasses import dataclass
from typing import Tuple

from epuck_vrep_compat.compat import cell_names


@dataclass(frozen=True)
class Robot:
    """One robot of the cell: its label in node and topic names, and its V-REP names."""

    label: str                      # "Comau": nodes [/Comau], [/NComau_PosOrAss], ...
    param_prefix: str               # the hub's parameters ~<prefix>_robot, ~<prefix>_joints
    robot_name: str                 # V-REP name of the robot's base object
    joint_names: Tuple[str, ...]    # V-REP names of its joints, in the handle message's order

    @property
    def handles_topic(self) -> str:
        return f"/{self.label}Handles"

    @property
    def joint_handles_topic(self) -> str:
        return f"/{self.label}_JointHandles"

    def poses_topic(self, absolute: bool) -> str:
        return f"/{self.label}_PosOr{'Ass' if absolute else 'Rel'}"

    def poses_node(self, absolute: bool) -> str:
        return f"N{self.label}_PosOr{'Ass' if absolute else 'Rel'}"


# Object names: the cell's robots (one table, cell_names.py).
COMAU = Robot("Comau", "comau", cell_names.COMAU_SMART_SIX.base_link,
              cell_names.COMAU_SMART_SIX.joints)
IRB = Robot("Irb", "irb", cell_names.IRB140.base_link, cell_names.IRB140.joints)
YOUBOT = Robot("YouBot", "youbot", cell_names.YOUBOT.base_link, cell_names.YOUBOT.joints)
ROBOTS = {robot.label: robot for robot in (COMAU, IRB, YOUBOT)}

HUB_NODE = "robot"

# The eleven proximity sensors on the IRB 140, in the order of /prox_data.
PROX_NODE = "proxSensors"
PROX_TOPIC = "/prox_data"
PROX_SENSOR_NAMES = tuple(f"Proximity_sensor{i}" for i in range(10, 21))


@dataclass(frozen=True)
class Camera:
    """One ceiling camera of the cell: its node, its V-REP vision sensor and its topic."""

    node: str
    sensor_name: str                # V-REP vision sensor (the thesis's names, as they are)
    topic: str


CAMERAS = {
    0: Camera("telecamera_0", "camera0", "/Camera_Image_0"),
    1: Camera("telecamera_1", "camera", "/Camera_Image_1"),
}

KINECT_NODE = "kinect"
KINECT_DEPTH_SENSOR = "kinect_depth"
KINECT_RGB_SENSOR = "kinect_rgb"
KINECT_DEPTH_BUFFER_TOPIC = "/kinect/depth_buffer"     # std_msgs/Float32MultiArray, V-REP 0..1
KINECT_RGB_IMAGE_TOPIC = "/kinect/rgb/image"           # sensor_msgs/Image rgb8

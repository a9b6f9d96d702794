"""One robot the speed-and-separation supervisor (:mod:`ssm_supervisor`) watches: its joint
states in, its speed scale and reports out, the speeds of its links' points from its
description, its joint states and its root's motion on TF."""
import math

import numpy as np
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Float64, String

from epuck_vrep_compat.compat.cell_names import ros_robot_name
from epuck_vrep_compat.compat.topics import (
    JOINT_STATES_TOPIC, ROBOT_DESCRIPTION_PARAM, SPEED_SCALE_TOPIC)
from epuck_vrep_compat.nodes.link_speeds import LinkSpeeds, root_twist
from epuck_vrep_compat.nodes.node_reset import forget_latched
from epuck_vrep_compat.nodes.ssm_model import ArmGovernor
from epuck_vrep_compat.nodes.ssm_pacing import lookup_root


class RobotChannel:
    """One supervised robot: its joint states in, its scale and reports out."""

    def __init__(self, name, p, lockstep=False, on_joints=None):
        """``lockstep``: the scale is latched (see :mod:`ssm_pacing`); ``on_joints(stamp)``:
        called after each joint state message."""
        self.name = name
        self._on_joints_hook = on_joints
        self.ros_name = ros_name = ros_robot_name(name)     # a copy's IRB140#0: IRB140_0
        self.p = p
        self.start_state()
        self.joints_subscriber = rospy.Subscriber(JOINT_STATES_TOPIC.format(robot=ros_name),
                                                  JointState, self._on_joints, queue_size=1)
        ns = f"~{ros_name}/"
        # in lock-step the simulator waits for it: written at once, by the cycle's thread
        self.command = rospy.Publisher(SPEED_SCALE_TOPIC.format(robot=ros_name), Float64,
                                       queue_size=None if lockstep else 1, latch=lockstep)
        self.out = {k: rospy.Publisher(ns + k, Float64, queue_size=1)
                    for k in ("separation", "protective_separation", "scale",
                              "operator_uncertainty")}
        self.stop_pub = rospy.Publisher(ns + "protective_stop", Bool, queue_size=1)
        self.status_pub = rospy.Publisher(ns + "status", String, queue_size=1, latch=True)

    def start_state(self):
        """What a run changes, as at the start."""
        self.governor = ArmGovernor(self.p)
        self.joints = None
        self.kinematics = None
        self.root_pose = None        # (stamp, position, quaternion) of the root on TF
        self.root_velocity = (None, None)     # its (linear, angular), root frame; None: rest
        self.status = None

    def restart(self):
        """As at the start (the supervisor reset): its state, and no latched scale or status
        for a new subscriber until it publishes again."""
        self.start_state()
        forget_latched(self.command)
        forget_latched(self.status_pub)

    def _on_joints(self, msg):
        self.joints = msg
        if self._on_joints_hook is not None:
            self._on_joints_hook(msg.header.stamp)

    def root_frame(self):
        """The robot's root link (its TF frame), or None while its description is unknown."""
        if self.kinematics is None:
            description = rospy.get_param(ROBOT_DESCRIPTION_PARAM.format(robot=self.ros_name), None)
            if description is None:
                return None
            self.kinematics = LinkSpeeds(description)
        return self.kinematics.root

    def link_speeds(self, links, local_points, tf_buffer, stamp=None):
        """Speeds of the points, or None while the robot's description or its root's frame
        on TF is unknown; the root's frame at ``stamp`` (None: the latest)."""
        root = self.root_frame()
        t = lookup_root(tf_buffer, root, stamp) if root is not None else None
        if t is None:
            return None
        p, r = t.transform.translation, t.transform.rotation
        pose = (t.header.stamp.to_sec(), np.array([p.x, p.y, p.z]),
                np.array([r.x, r.y, r.z, r.w]))
        if self.root_pose is None:
            self.root_pose = pose
        elif pose[0] > self.root_pose[0]:       # a new frame: the twist since the last one
            self.root_velocity = root_twist(self.root_pose, pose)
            self.root_pose = pose
        linear, angular = self.root_velocity
        j = self.joints
        return self.kinematics.speeds(j.name, j.position, j.velocity or [0.0] * len(j.name),
                                      links, local_points, linear, angular)

    def report(self, separation, s_p, scale, status, z_d=math.nan):
        self.command.publish(Float64(scale))
        for key, value in (("separation", separation), ("protective_separation", s_p),
                           ("scale", scale), ("operator_uncertainty", z_d)):
            self.out[key].publish(Float64(value))
        self.stop_pub.publish(Bool(scale <= 0.0))
        if status != self.status:
            self.status = status
            self.status_pub.publish(String(status))

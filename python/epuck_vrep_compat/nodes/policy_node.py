"""Runs a controller on an e-puck's ROS topics, in any topic profile, with the observation
builder the learning environments use (:mod:`epuck_vrep_compat.policy`): a policy trained in
``epuck_vrep_compat.learn`` runs here unchanged, on the simulator or on the real robot.

    rosrun epuck_vrep_compat policy_node _weights:=evolved.json _profile:=epuck_driver
    rosrun epuck_vrep_compat policy_node _policy:=my_pkg.my_module:act _robot:=ePuck1

Parameters: ``~weights`` (a perceptron weights file, default the shipped avoider
``config/avoider.json``) or ``~policy`` (``pkg.module:function``: ``function(obs)``
returns the two wheel speeds in [-1, 1]; its layout from ``~imu``, ``~neighbours``,
``~neighbour_range_m``, ``~camera``, ``~camera_bins``), ``~profile`` (vrep, epuck_driver,
epuck2_driver), ``~robot`` (the profile's first robot), ``~cmd_vel_scaling`` (the profile's
default, the simulator's), ``~others`` (robot names whose ``ground_truth`` gives the
neighbours' block).
It answers each sensor cycle once (:mod:`epuck_vrep_compat.nodes.ir_cycle`): when the eight
``proximity`` readings of one step are in, it builds the observation (with the latest IMU and
poses and camera row: the last ``camera`` image, rgb8 or mono8, zeros until the first), calls
the policy and publishes the wheel speeds as the profile's ``cmd_vel``.
"""
import importlib
import os

import numpy as np
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, Imu, Range

from epuck_vrep_compat.compat import epuck_names
from epuck_vrep_compat.compat.cmd_vel import (MAX_WHEEL_SPEED_RAD_S, PROFILE_SCALINGS, SCALINGS,
                                              twist_for_wheels)
from epuck_vrep_compat.geometry.transforms import yaw_of
from epuck_vrep_compat.nodes.ir_cycle import IrCycle
from epuck_vrep_compat.policy import neighbours as nb
from epuck_vrep_compat.policy import observation
from epuck_vrep_compat.policy.controller import Perceptron
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.common.params import ParamError, read_typed

PROFILES = epuck_names.PROFILE_NAMES
SHIPPED_WEIGHTS = os.path.join("config", "avoider.json")


def load_function(spec: str):
    """``pkg.module:function`` -> the function; ParamError naming ``~policy`` otherwise."""
    module, colon, name = spec.partition(":")
    if not colon or not module or not name:
        raise ParamError(f"parameter '~policy' must be 'pkg.module:function', got {spec!r}")
    try:
        return getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError) as e:
        raise ParamError(f"parameter '~policy' {spec!r}: {e}") from e


def shipped_weights() -> str:
    import rospkg
    return os.path.join(rospkg.RosPack().get_path("epuck_vrep_compat"), SHIPPED_WEIGHTS)


class PolicyRunner:
    """The latest readings of one robot, and a command from the policy for each IR cycle."""

    def __init__(self, policy, layout, scaling, robot):
        self.policy, self.layout, self.scaling, self.robot = policy, layout, scaling, robot
        self.accel = np.array([0.0, 0.0, observation.ACCEL_UNIT_M_S2])
        self.gyro = np.zeros(3)
        self.poses = {}
        self.camera = np.zeros(layout.camera_bins)
        self.last_observation = None
        self._log = ThrottledLog()

    def on_imu(self, msg):
        a, g = msg.linear_acceleration, msg.angular_velocity
        self.accel, self.gyro = np.array([a.x, a.y, a.z]), np.array([g.x, g.y, g.z])

    def on_camera(self, msg):
        try:
            image = observation.image_from_buffer(msg.data, msg.width, msg.height, msg.step,
                                                  msg.encoding)
        except ValueError as e:
            self._log.warn("camera", "policy_node: camera image ignored: %s", e)
            return
        self.camera = observation.camera_row(image, self.layout.camera_bins)

    def on_pose(self, msg, name):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.poses[name] = (p.x, p.y, float(yaw_of((q.x, q.y, q.z, q.w))))

    def observe(self, ranges_m):
        block = None
        if self.layout.neighbours:
            own = self.poses.get(self.robot)
            others = [p[:2] for n, p in self.poses.items() if n != self.robot]
            block = (np.zeros(3 * self.layout.neighbours) if own is None else
                     nb.block(own, others, self.layout.neighbours, self.layout.neighbour_range_m))
        return observation.build(self.layout, ranges_m, self.accel, self.gyro, block,
                                 self.camera)

    def control(self, ranges_m, _max_ranges_m):
        """(linear.x, angular.z) for this cycle's eight ranges."""
        self.last_observation = self.observe(ranges_m)
        wheels = np.clip(np.asarray(self.policy(self.last_observation), float).reshape(2),
                         -1.0, 1.0) * MAX_WHEEL_SPEED_RAD_S
        return twist_for_wheels(self.scaling, float(wheels[0]), float(wheels[1]))


def read_config():
    """(policy, layout, profile names, robot, scaling, others) from the private parameters."""
    profile = read_typed("profile", "vrep", str, lambda v: v in PROFILES,
                         f"must be one of {sorted(PROFILES)}")
    names = PROFILES[profile]
    robot = read_typed("robot", names.robot_name(0), str, bool, "must be a robot name")
    scaling = read_typed("cmd_vel_scaling", PROFILE_SCALINGS[profile], str,
                         lambda v: v in SCALINGS, f"must be one of {list(SCALINGS)}")
    others = rospy.get_param("~others", [])
    if not isinstance(others, list) or not all(isinstance(o, str) and o for o in others):
        raise ParamError(f"parameter '~others' must be a list of robot names, got {others!r}")
    spec = read_typed("policy", "", str)
    if spec:
        policy = load_function(spec)
        layout = observation.ObservationLayout(
            imu=read_typed("imu", False, bool),
            neighbours=read_typed("neighbours", 0, int, lambda v: v >= 0, "must be >= 0"),
            neighbour_range_m=read_typed("neighbour_range_m", 0.5, float, lambda v: v > 0,
                                         "must be > 0"),
            camera=read_typed("camera", False, bool),
            camera_bins=read_typed("camera_bins", observation.CAMERA_BINS, int,
                                   lambda v: v >= 1, "must be >= 1"))
    else:
        path = read_typed("weights", "", str) or shipped_weights()
        try:
            policy = Perceptron.load(path)
        except ValueError as e:
            raise ParamError(f"parameter '~weights': {e}") from e
        layout = policy.layout
    return policy, layout, names, robot, scaling, others


def main():
    rospy.init_node("policy_node")
    try:
        policy, layout, names, robot, scaling, others = read_config()
    except ParamError as e:
        rospy.logfatal("policy_node: %s", e)
        return 2
    runner = PolicyRunner(policy, layout, scaling, robot)
    pub = rospy.Publisher(names.topic(robot, "cmd_vel"), Twist, queue_size=1)
    cycle = IrCycle(runner.control, pub)
    subs = [rospy.Subscriber(names.topic(robot, f"proximity{k}"), Range, cycle.on_range, k,
                             queue_size=8) for k in range(epuck_names.PROXIMITY_COUNT)]
    if layout.imu:
        subs.append(rospy.Subscriber(names.topic(robot, "imu"), Imu, runner.on_imu,
                                     queue_size=1))
    if layout.camera:
        subs.append(rospy.Subscriber(names.topic(robot, "camera"), Image, runner.on_camera,
                                     queue_size=1, buff_size=2 ** 20))
    if layout.neighbours:
        subs += [rospy.Subscriber(names.topic(name, "ground_truth"), Odometry, runner.on_pose,
                                  name, queue_size=1) for name in [robot] + list(others)]
    rospy.loginfo("policy_node: %s in profile %s, observation %s, cmd_vel %s", robot,
                  names.name, layout.names, scaling)
    rospy.spin()
    del subs
    return 0

#!/usr/bin/python3
"""Parity of the two faces of a policy: with noise off, the observation the learning
environment builds for a world state equals, within 1e-6, the one the policy package's builder
makes from the ROS topics of the same state (the eight ``proximity`` ranges, the IMU, the
robots' ``ground_truth`` for the neighbours' block, the ``camera`` image for the camera row),
in the profile ``~profile``.

The simulator runs ``worlds/learn_arena.yaml`` (the learning arena, six cylinders, two robots
near the east wall); the test reads one step's topics, then builds the same arena in a
``BatchedWorlds`` (walls of ``learn/tasks.py``, the scene's cylinders, the robots at the
ground-truth poses) through the environments' ``Worlds`` and compares.

The camera is published at its rate (4 Hz), below the step's: the step compared is one whose
stamp every topic, the camera image too, carries. Robot 0 faces the east wall from 3 cm (its
camera row is the wall's shade); robot 1's camera sees robot 0's body, so its camera block is
compared too, at a step its image carries (each camera keeps its own 4 Hz phase). The environment renders its camera with the
simulator's camera (the profile's size and field of view: rgb8 40 x 40 in ``vrep``, the
drivers' mono8 160 x 2 slice) through the same core call from the same poses, so its image is
the topic's pixel for pixel (mono8: the same rounded luma) and the camera block is held to the
other blocks' 1e-6 (a pose read back from ``ground_truth`` differs by at most an ulp of yaw,
which moves no ray across an edge here)."""
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, Imu, Range

from epuck_vrep_compat.learn import tasks
from epuck_vrep_compat.learn.worlds import Worlds
from epuck_vrep_compat.policy import neighbours, observation
from epuck_vrep_compat.ros.node.params import read_params

from sim_test_helpers import PKG, learn_test_setup, pose_of

LAYOUT = observation.ObservationLayout(imu=True, neighbours=1, neighbour_range_m=0.5,
                                       camera=True)
CAMERA = slice(LAYOUT.size - LAYOUT.camera_bins, LAYOUT.size)
SETTLED_S = 0.5            # read a step after this much simulated time


class StepReadings:
    """Every message of the robots' topics, by stamp, until one stamp has all those wanted."""

    def __init__(self, names, robots):
        self.lock = threading.Lock()
        self.by_stamp = {}
        me = robots[0]
        self.subs = [rospy.Subscriber(names.topic(me, f"proximity{k}"), Range, self.keep,
                                      ("range", k)) for k in range(8)]
        self.subs.append(rospy.Subscriber(names.topic(me, "imu"), Imu, self.keep, ("imu", 0)))
        self.subs += [rospy.Subscriber(names.topic(r, "ground_truth"), Odometry, self.keep,
                                       ("pose", i)) for i, r in enumerate(robots)]
        self.subs += [rospy.Subscriber(names.topic(r, "camera"), Image, self.keep, ("camera", i))
                      for i, r in enumerate(robots)]

    def keep(self, msg, key):
        stamp = msg.header.stamp.to_sec()
        with self.lock:
            self.by_stamp.setdefault(stamp, {})[key] = msg

    def complete(self, wanted, timeout_s=60.0):
        """The messages of the first step after SETTLED_S with every key of ``wanted``."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            with self.lock:
                for stamp in sorted(self.by_stamp):
                    if stamp >= SETTLED_S and set(wanted) <= set(self.by_stamp[stamp]):
                        return self.by_stamp[stamp]
            time.sleep(0.05)
        raise AssertionError("no step with every topic within the time limit")


def camera_block(image):
    """The camera row of a sensor_msgs/Image, by the policy package's builder."""
    return observation.camera_row(observation.image_from_buffer(
        image.data, image.width, image.height, image.step, image.encoding), LAYOUT.camera_bins)


class LearnParity(unittest.TestCase):
    def test_environment_and_topics_give_the_same_observation(self):
        guard, names, scene = learn_test_setup("test_learn_parity")
        robots = [names.robot_name(0), names.robot_name(1)]
        readings = StepReadings(names, robots)
        poses_wanted = [("pose", i) for i in range(len(robots))]
        got = readings.complete([("range", k) for k in range(8)] + [("imu", 0), ("camera", 0)]
                                + poses_wanted)

        ranges = [got[("range", k)].range for k in range(8)]
        imu = got[("imu", 0)]
        accel = [imu.linear_acceleration.x, imu.linear_acceleration.y, imu.linear_acceleration.z]
        gyro = [imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z]
        poses = [pose_of(got[("pose", i)]) for i in range(len(robots))]
        block = neighbours.block(poses[0], [p[:2] for p in poses[1:]], 1, 0.5)
        image = got[("camera", 0)]
        from_topics = observation.build(LAYOUT, ranges, accel, gyro, block, camera_block(image))

        # the simulator's camera: the profile's, as the node read its parameters (this test
        # has the node's ~profile and ~world and none of its camera parameters)
        spec = read_params(rospy.get_param("~world")).camera
        self.assertEqual((image.width, image.height, image.encoding),
                         (spec.width, spec.height, {"vrep": "rgb8"}.get(names.name, "mono8")))
        from_env = self.environment_observations(scene, poses, spec)[0]
        self.assertGreater(int(np.sum(from_env[:8] > 0.0)), 4, "the state should be seen by "
                           f"several sensors: {from_env[:8]}")
        self.assertGreater(from_env[14], 0.0, "robot 1 should be in the neighbours' range")
        np.testing.assert_allclose(from_topics, from_env, rtol=0, atol=1e-6,
                                   err_msg=f"{names.name}: {LAYOUT.names}")

        got = readings.complete([("camera", 1)] + poses_wanted)       # robot 1's camera
        poses = [pose_of(got[("pose", i)]) for i in range(len(robots))]
        from_env = self.environment_observations(scene, poses, spec)[1, CAMERA]
        self.assertGreater(len(np.unique(np.round(from_env, 6))), 3,
                           f"robot 1's camera should see robot 0's body: {from_env}")
        np.testing.assert_allclose(camera_block(got[("camera", 1)]), from_env, rtol=0,
                                   atol=1e-6, err_msg=f"{names.name}: robot 1's camera row")
        self.assertEqual(guard.errors, [])

    def environment_observations(self, scene, poses, camera):
        """The observations (R, D) of the robots from the environments' Worlds in the same
        state, their cameras rendered with ``camera`` (a CameraSpec)."""
        worlds = Worlds(tasks.Task("obstacle_avoidance", len(poses), LAYOUT), 1, noise="ideal",
                        multi_agent=True, camera=camera)
        worlds.build(0, tasks.scene_cylinders(scene), 0, np.array(poses))
        for _ in range(int(SETTLED_S / worlds.dt_s) + 1):
            worlds.step(np.zeros((1, len(poses), 2)), rest=[True])
        return worlds.agent_obs()[0].astype(float)


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_learn_parity", LearnParity)

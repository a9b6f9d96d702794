#!/usr/bin/python3
"""Parity of the two faces of a policy: with noise off, the observation the learning
environment builds for a world state equals, within 1e-6, the one the policy package's builder
makes from the ROS topics of the same state (the eight ``proximity`` ranges, the IMU, the
robots' ``ground_truth`` for the neighbours' block), in the profile ``~profile``.

The simulator runs ``worlds/learn_arena.yaml`` (the learning arena, six cylinders, two robots
near the east wall); the test reads one step's topics, then builds the same arena in a
``BatchedWorlds`` (walls of ``learn/tasks.py``, the scene's cylinders, the robots at the
ground-truth poses) through the environments' ``Worlds`` and compares."""
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, Range

from epuck_vrep_compat.learn import tasks
from epuck_vrep_compat.learn.worlds import Worlds
from epuck_vrep_compat.policy import neighbours, observation

from sim_test_helpers import PKG, learn_test_setup, pose_of

LAYOUT = observation.ObservationLayout(imu=True, neighbours=1, neighbour_range_m=0.5)
SETTLED_S = 0.5            # read a step after this much simulated time


class StepReadings:
    """Every message of the robots' topics, by stamp, until one stamp has them all."""

    def __init__(self, names, robots):
        self.lock = threading.Lock()
        self.by_stamp = {}
        self.wanted = 8 + 1 + len(robots)
        me = robots[0]
        self.subs = [rospy.Subscriber(names.topic(me, f"proximity{k}"), Range, self.keep,
                                      ("range", k)) for k in range(8)]
        self.subs.append(rospy.Subscriber(names.topic(me, "imu"), Imu, self.keep, ("imu", 0)))
        self.subs += [rospy.Subscriber(names.topic(r, "ground_truth"), Odometry, self.keep,
                                       ("pose", i)) for i, r in enumerate(robots)]

    def keep(self, msg, key):
        stamp = msg.header.stamp.to_sec()
        with self.lock:
            self.by_stamp.setdefault(stamp, {})[key] = msg

    def complete(self, timeout_s=60.0):
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            with self.lock:
                for stamp in sorted(self.by_stamp):
                    if stamp >= SETTLED_S and len(self.by_stamp[stamp]) == self.wanted:
                        return self.by_stamp[stamp]
            time.sleep(0.05)
        raise AssertionError("no step with every topic within the time limit")


class LearnParity(unittest.TestCase):
    def test_environment_and_topics_give_the_same_observation(self):
        guard, names, scene = learn_test_setup("test_learn_parity")
        robots = [names.robot_name(0), names.robot_name(1)]
        got = StepReadings(names, robots).complete()

        ranges = [got[("range", k)].range for k in range(8)]
        imu = got[("imu", 0)]
        accel = [imu.linear_acceleration.x, imu.linear_acceleration.y, imu.linear_acceleration.z]
        gyro = [imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z]
        poses = [pose_of(got[("pose", i)]) for i in range(len(robots))]
        block = neighbours.block(poses[0], [p[:2] for p in poses[1:]], 1, 0.5)
        from_topics = observation.build(LAYOUT, ranges, accel, gyro, block)

        from_env = self.environment_observation(scene, poses)
        self.assertGreater(int(np.sum(from_env[:8] > 0.0)), 4, "the state should be seen by "
                           f"several sensors: {from_env[:8]}")
        self.assertGreater(from_env[14], 0.0, "robot 1 should be in the neighbours' range")
        np.testing.assert_allclose(from_topics, from_env, rtol=0, atol=1e-6,
                                   err_msg=f"{names.name}: {LAYOUT.names}")
        self.assertEqual(guard.errors, [])

    def environment_observation(self, scene, poses):
        """The observation of robot 0 from the environments' Worlds in the same state."""
        arena = scene.arena
        self.assertEqual((tuple(arena.size_m), arena.wall_thickness_m, arena.wall_height_m),
                         ((tasks.ARENA_SIDE_M,) * 2, tasks.WALL_THICKNESS_M,
                          tasks.WALL_HEIGHT_M), "the scene must be the learning arena")
        worlds = Worlds(tasks.Task("obstacle_avoidance", len(poses), LAYOUT), 1, noise="ideal",
                        multi_agent=True)
        core = worlds.core
        core.clear_obstacles(0)
        for centre, half, yaw in worlds.task.walls():
            core.add_box(0, np.array(centre), np.array(half), yaw)
        for o in scene.obstacles:
            self.assertEqual(o.shape, "cylinder")
            core.add_cylinder(0, np.array([*o.position_m, 0.5 * o.height_m]), o.radius_m,
                              o.height_m)
        core.reset_world(0, 0)
        for r, (x, y, yaw) in enumerate(poses):
            core.set_pose(0, r, x, y, yaw)
        for _ in range(int(SETTLED_S / worlds.dt_s) + 1):
            worlds.step(np.zeros((1, len(poses), 2)), rest=[True])
        return worlds.agent_obs()[0, 0].astype(float)


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_learn_parity", LearnParity)

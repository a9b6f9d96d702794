#!/usr/bin/python3
"""policy_node with the shipped weights drives ePuck0 in the profile ``~profile`` (and its
default cmd_vel scaling): started 3 cm from the east wall of the learning arena
(worlds/learn_arena.yaml), it turns away, drives on and touches no wall or cylinder for
``~duration_s`` of simulated time (the clearance of its body, from ground truth, stays > 0)."""
import threading
import unittest

import numpy as np
import rospy
import rostest
from nav_msgs.msg import Odometry

from epuck_vrep_compat.learn.tasks import BODY_RADIUS_M

from sim_test_helpers import PKG, learn_test_setup, pose_of


def clearance(scene, x, y):
    """The gap between the robot's body at (x, y) and the nearest wall or cylinder [m]."""
    half_x, half_y = 0.5 * scene.arena.size_m[0], 0.5 * scene.arena.size_m[1]
    gaps = [half_x - abs(x), half_y - abs(y)]
    gaps += [float(np.hypot(x - o.position_m[0], y - o.position_m[1])) - o.radius_m
             for o in scene.obstacles]
    return min(gaps) - BODY_RADIUS_M


class PolicyNodeDrives(unittest.TestCase):
    def test_drives_away_from_the_wall_without_contact(self):
        guard, names, scene = learn_test_setup("test_learn_policy_node")
        duration = float(rospy.get_param("~duration_s", 20.0))
        poses, lock, done = [], threading.Lock(), threading.Event()

        def on_pose(msg):
            with lock:
                poses.append((msg.header.stamp.to_sec(), *pose_of(msg)))
                if poses[-1][0] >= duration:
                    done.set()
        sub = rospy.Subscriber(names.topic(names.robot_name(0), "ground_truth"), Odometry,
                               on_pose, queue_size=100)
        self.assertTrue(done.wait(600.0), "simulated time did not reach the duration")
        sub.unregister()
        with lock:
            track = np.array(poses)
        gaps = [clearance(scene, x, y) for _, x, y, _ in track]
        path = float(np.sum(np.hypot(np.diff(track[:, 1]), np.diff(track[:, 2]))))
        start_gap = clearance(scene, *track[0, 1:3])
        self.assertLess(start_gap, 0.04, "the start should be close to the wall")
        self.assertGreater(path, 0.5, f"drove only {path:.3f} m in {duration} s")
        self.assertGreater(min(gaps), 0.0, f"touched something: clearance {min(gaps):.4f} m")
        self.assertEqual(guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_learn_policy_node", PolicyNodeDrives)

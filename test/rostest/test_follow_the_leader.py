#!/usr/bin/python3
"""The follow-the-leader demo converges: the follower keeps the gap while the leader wanders."""
import math
import unittest

import numpy as np
import rospy
import rostest
import tf2_ros

from sim_test_helpers import PKG, RosoutGuard, wait_sim_time

GAP_M = 0.12


class FollowTheLeader(unittest.TestCase):
    def test_follower_keeps_the_gap(self):
        rospy.init_node("test_follow_the_leader")
        guard = RosoutGuard()
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        buf.lookup_transform("odom", "ePuck1/base_link", rospy.Time(0), rospy.Duration(30.0))
        start = buf.lookup_transform("odom", "ePuck0/base_link", rospy.Time(0)).transform
        wait_sim_time(8.0)                          # converge from the start poses
        distances, leader_path = [], 0.0
        last = (start.translation.x, start.translation.y)
        for _ in range(60):                          # 12 s of simulated time
            wait_sim_time(0.2)
            t = buf.lookup_transform("ePuck1/base_link", "ePuck0/base_link", rospy.Time(0))
            distances.append(math.hypot(t.transform.translation.x, t.transform.translation.y))
            leader = buf.lookup_transform("odom", "ePuck0/base_link", rospy.Time(0)).transform
            leader_path += math.hypot(leader.translation.x - last[0],
                                      leader.translation.y - last[1])
            last = (leader.translation.x, leader.translation.y)
        errors = np.abs(np.array(distances) - GAP_M)
        self.assertGreater(leader_path, 0.3, "the leader should be moving")
        self.assertLess(float(errors.mean()), 0.03, f"distances {distances}")
        self.assertLess(float(errors.max()), 0.08, f"distances {distances}")
        self.assertEqual(guard.errors, [])



if __name__ == "__main__":
    rostest.rosrun(PKG, "test_follow_the_leader", FollowTheLeader)

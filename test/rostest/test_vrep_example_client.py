#!/usr/bin/python3
"""vrep_example_client (V-REP's rosBubbleRob, ported) against the simulator: it enables its
streams, drives ePuck0, and ends with exit code 0 when the simulation is stopped."""
import math
import subprocess
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from vrep_common.srv import simRosStopSimulation

from sim_test_helpers import PKG, wait_for_message, wait_sim_time

RUN_SIM_S = 6.0
EXIT_TIMEOUT_S = 20.0
MIN_TRAVEL_M = 0.05


class VrepExampleClient(unittest.TestCase):
    def test_drives_and_exits_when_the_simulation_stops(self):
        rospy.init_node("test_vrep_example_client")
        start = wait_for_message("/ePuck0/ground_truth", Odometry).pose.pose.position
        client = subprocess.Popen(["rosrun", PKG, "vrep_example_client"])
        try:
            wait_sim_time(RUN_SIM_S)
            self.assertIsNone(client.poll(), "the client ended while the simulation ran")
            now = wait_for_message("/ePuck0/ground_truth", Odometry).pose.pose.position
            travel = math.hypot(now.x - start.x, now.y - start.y)
            self.assertGreater(travel, MIN_TRAVEL_M, "ePuck0 did not move")
            rospy.wait_for_service("/vrep/simRosStopSimulation", timeout=10.0)
            stop = rospy.ServiceProxy("/vrep/simRosStopSimulation", simRosStopSimulation)
            self.assertEqual(stop().result, 1)
            self.assertEqual(client.wait(timeout=EXIT_TIMEOUT_S), 0)
        finally:
            if client.poll() is None:
                client.kill()
                client.wait()


if __name__ == "__main__":
    rostest.rosrun(PKG, "vrep_example_client_run", VrepExampleClient)

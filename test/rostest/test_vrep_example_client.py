#!/usr/bin/python3
"""vrep_example_client (V-REP's rosBubbleRob, ported) against the simulator: it enables its
streams, drives ePuck0, and ends with exit code 0 when the simulation is stopped."""
import math
import subprocess
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from vrep_common.srv import simRosStopSimulation

from sim_test_helpers import PKG, wait_for_message, wait_sim_time

RUN_SIM_S = 6.0
START_TIMEOUT_S = 60.0    # wall time for the client to start and send its first wheel command
EXIT_TIMEOUT_S = 20.0
MIN_TRAVEL_M = 0.05


class VrepExampleClient(unittest.TestCase):
    def test_drives_and_exits_when_the_simulation_stops(self):
        rospy.init_node("test_vrep_example_client")
        client = subprocess.Popen(["rosrun", PKG, "vrep_example_client"])
        try:
            # counted from its first wheel command, not from its start: a loaded machine may
            # take long to start a Python node, and the simulator runs on meanwhile
            wheels = self._first_wheel_command(client)
            start = wait_for_message("/ePuck0/ground_truth", Odometry).pose.pose.position
            wheels.unregister()
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

    def _first_wheel_command(self, client):
        """The subscription to the client's wheels topic (/vrep_example_client<id>/wheels)
        once its first command has come."""
        from vrep_common.msg import JointSetStateData
        deadline = time.monotonic() + START_TIMEOUT_S
        got, wheels = [], None
        while not got:
            self.assertIsNone(client.poll(), "the client ended before driving")
            self.assertLess(time.monotonic(), deadline,
                            f"no wheel command from the client within {START_TIMEOUT_S} s")
            if wheels is None:
                topics = [t for t, _ in rospy.get_published_topics()
                          if t.startswith("/vrep_example_client") and t.endswith("/wheels")]
                if topics:
                    wheels = rospy.Subscriber(topics[0], JointSetStateData, got.append,
                                              queue_size=1)
            time.sleep(0.05)
        return wheels


if __name__ == "__main__":
    rostest.rosrun(PKG, "vrep_example_client_run", VrepExampleClient)

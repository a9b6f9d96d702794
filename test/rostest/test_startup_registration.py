#!/usr/bin/python3
"""Start-up with 150 robots: every topic reaches the master, clients that came first are served.

The test node starts together with the simulator, so its subscriber and its latched ``cmd_vel``
publisher exist while the simulator is still registering (bulk registration from a background
thread, ``ros/transport/registration.py``): the master must hand each side to the other.
"""
import time

import rosgraph.masterapi
import rospy
import rostest
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Range

from sim_test_helpers import PKG, Collector, RosoutGuard, SimTestCase, wait_for_message

N = 150
LAST = f"ePuck{N - 1}"
TIMEOUT_S = 120.0
PER_ROBOT_PUBLISHED = [f"proximity{k}" for k in range(8)] + ["imu", "ground_truth",
                                                              "led_state", "camera"]
PER_ROBOT_SUBSCRIBED = ["cmd_vel", "cmd_led"]


def missing_registrations():
    """Per-robot topics the master does not list for /vrep yet."""
    publishers, subscribers, _ = rosgraph.masterapi.Master("/test").getSystemState()
    published = {t for t, nodes in publishers if "/vrep" in nodes}
    subscribed = {t for t, nodes in subscribers if "/vrep" in nodes}
    missing = [f"/ePuck{i}/{r}" for i in range(N) for r in PER_ROBOT_PUBLISHED
               if f"/ePuck{i}/{r}" not in published]
    return missing + [f"/ePuck{i}/{r}" for i in range(N) for r in PER_ROBOT_SUBSCRIBED
                      if f"/ePuck{i}/{r}" not in subscribed]


class StartupRegistration(SimTestCase):
    NODE = "test_startup_registration"
    GUARD = False             # made after the first subscriptions (set-up below)

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        # first thing: subscribe and publish on the last robot's topics, which the simulator
        # registers last
        cls.ranges = Collector(f"/{LAST}/proximity0", Range)
        cls.cmd_vel = rospy.Publisher(f"/{LAST}/cmd_vel", Twist, queue_size=1, latch=True)
        cls.cmd_vel.publish(Twist())
        cls.guard = RosoutGuard()
        wait_for_message("/clock", Clock, timeout_s=TIMEOUT_S)

    def test_every_robots_topics_reach_the_master(self):
        deadline = time.monotonic() + TIMEOUT_S
        missing = missing_registrations()
        while missing and time.monotonic() < deadline:
            time.sleep(0.2)
            missing = missing_registrations()
        self.assertEqual(missing[:10], [], f"{len(missing)} registrations missing")

    def test_an_early_subscriber_gets_the_last_robots_readings(self):
        msgs = self.ranges.wait(3, timeout_s=TIMEOUT_S)
        self.assertEqual(msgs[0].header.frame_id, f"{LAST}/base_prox0")
        stamps = [m.header.stamp.to_sec() for m in msgs]
        self.assertEqual(stamps, sorted(stamps))

    def test_an_early_latched_publisher_is_found_by_the_simulator(self):
        deadline = time.monotonic() + TIMEOUT_S
        while self.cmd_vel.get_num_connections() == 0 and time.monotonic() < deadline:
            time.sleep(0.1)
        self.assertEqual(self.cmd_vel.get_num_connections(), 1)

    def test_zz_no_error_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "startup_registration", StartupRegistration)

#!/usr/bin/python3
"""Every topic of a simulator that runs flat out, subscribed by one client at once.

rospy's TCPROS server queues 5 connections not yet accepted, and accepts from one Python
thread that a simulator running flat out leaves little time: a client opening one connection
per topic at once (roscpp's ``rosbag record -a`` or a benchmark's subscriber) overflowed that
queue, and the simulator did not see about a third of them (the client's side counted them as
open) for as long as TCP kept retrying. The simulator widens the queue
(``ros/transport/accept_queue.py``). Here a client speaks TCPROS itself so that its connections
arrive together, as roscpp's do: every one must reach the simulator and deliver, and the
simulator's descriptors must grow with its connections, not with its topics.
"""
import os
import time
import unittest
import xmlrpc.client

import rosgraph.masterapi
import rospy
import rostest
from rosgraph_msgs.msg import Clock

from raw_tcpros import RawSubscriber, pump, subscribe_all, tcpros_address
from sim_test_helpers import PKG, simulator_topics, wait_for_message

N = 10
TIMEOUT_S = 30.0     # liveness only: with the queue widened every one connects within a second
PER_STEP = [f"proximity{k}" for k in range(8)] + ["imu", "ground_truth"]
CALLER_ID = RawSubscriber.CALLER_ID


class SubscribeEverything(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_subscribe_everything")
        wait_for_message("/clock", Clock, timeout_s=120.0)
        published, _subscribed, _types = simulator_topics()
        cls.topics = sorted(published - {"/rosout"})
        cls.sim_uri = rosgraph.masterapi.Master(rospy.get_name()).lookupNode("/vrep")
        address = tcpros_address(cls.sim_uri, cls.topics[0])
        cls.subs = subscribe_all(cls.topics, address, TIMEOUT_S)

    @classmethod
    def tearDownClass(cls):
        for sub in cls.subs.values():
            sub.sock.close()

    def pump(self, until, timeout_s=TIMEOUT_S):
        """Read every socket until ``until()`` holds or the time is up."""
        pump(self.subs, until, timeout_s)

    def missing_at_the_simulator(self):
        _code, _msg, bus = xmlrpc.client.ServerProxy(self.sim_uri).getBusInfo(CALLER_ID)
        connected = {c[4] for c in bus if c[1] == CALLER_ID}
        return [t for t in self.topics if t not in connected]

    def test_1_the_simulator_accepts_every_connection(self):
        self.assertGreater(len(self.topics), N * 13)
        self.assertEqual([t for t, s in self.subs.items() if not s.sent], [])
        missing = self.missing_at_the_simulator()
        deadline = time.monotonic() + TIMEOUT_S
        while missing and time.monotonic() < deadline:
            self.pump(lambda: False, timeout_s=0.5)   # keep reading: nothing backs up
            missing = self.missing_at_the_simulator()
        self.assertEqual(missing, [], f"{len(missing)} of {len(self.topics)} connections never "
                                      "reached the simulator")

    def test_2_every_per_step_topic_delivers(self):
        per_step = [f"/ePuck{i}/{r}" for i in range(N) for r in PER_STEP] + ["/tf", "/clock"]
        self.assertEqual([t for t in per_step if t not in self.subs], [])
        silent = lambda: [t for t in per_step if self.subs[t].messages < 2]  # header + one
        self.pump(lambda: not silent())
        self.assertEqual(silent(), [], f"{len(silent())} of {len(per_step)} per-step topics "
                                       "delivered nothing")

    def test_3_descriptors_grow_with_connections_not_with_topics(self):
        # rospy gives each topic its own epoll descriptor: 15 000 at 1000 robots, which ran the
        # node out of descriptors (and its accept thread into EMFILE) after 5 000 of 13 001
        # subscriptions. The simulator's topics share one (ros/transport/accept_queue.py).
        _code, _msg, pid = xmlrpc.client.ServerProxy(self.sim_uri).getPid(CALLER_ID)
        descriptors = os.listdir(f"/proc/{pid}/fd")
        kinds = [_link(f"/proc/{pid}/fd/{fd}") for fd in descriptors]
        epolls = sum(k == "anon_inode:[eventpoll]" for k in kinds)
        _code, _msg, bus = xmlrpc.client.ServerProxy(self.sim_uri).getBusInfo(CALLER_ID)
        self.assertGreater(len(bus), len(self.topics))   # ours, and the test node's
        # a few of rospy's and the core's own, none per topic (there are over 150)
        self.assertLess(epolls, 10)
        self.assertLess(len(descriptors), len(bus) + 100)


def _link(path):
    """What a descriptor of the running simulator refers to; "" when it was closed between
    listing the folder and reading the link (the simulator keeps running)."""
    try:
        return os.readlink(path)
    except FileNotFoundError:
        return ""


if __name__ == "__main__":
    rostest.rosrun(PKG, "subscribe_everything", SubscribeEverything)

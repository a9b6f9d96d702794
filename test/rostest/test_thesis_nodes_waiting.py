#!/usr/bin/python3
"""The thesis's nodes without a simulator: [/robot] and [/proxSensors] wait for /vrep with a
clear, repeated /rosout line, publish nothing and do not die; a bad parameter is refused."""
import subprocess
import threading
import time

import rosnode
import rospy
import rostest
from rosgraph_msgs.msg import Log

from epuck_vrep_compat.msg import ComauMsg, vett_proxData
from sim_test_helpers import PKG, Collector, SimTestCase

WAITING = {"/robot": "waiting for /vrep/simRosGetObjectHandle",
           "/proxSensors": "waiting for /vrep/simRosGetObjectGroupData"}
WATCH_S = 12.0              # > two periods of the waiting line


class RosoutLines:
    def __init__(self):
        self._lock = threading.Lock()
        self.lines = []
        self._sub = rospy.Subscriber("/rosout", Log, self._cb, queue_size=1000)

    def _cb(self, msg):
        with self._lock:
            self.lines.append((msg.name, msg.level, msg.msg))

    def of(self, node):
        with self._lock:
            return [(level, text) for name, level, text in self.lines if name == node]


class ThesisNodesWaiting(SimTestCase):
    NODE = "test_thesis_nodes_waiting"
    GUARD = False

    def test_nodes_wait_for_the_simulator_and_stay_up(self):
        rosout = RosoutLines()
        handles = Collector("/ComauHandles", ComauMsg)
        prox = Collector("/prox_data", vett_proxData)
        time.sleep(WATCH_S)
        for node, line in WAITING.items():
            said = [text for _, text in rosout.of(node)]
            self.assertTrue(any(line in text for text in said),
                            f"{node} did not say '{line}'; it said {said}")
            self.assertGreaterEqual(sum(line in text for text in said), 2,
                                    f"{node} said '{line}' only once in {WATCH_S} s")
            errors = [text for level, text in rosout.of(node) if level >= Log.ERROR]
            self.assertEqual(errors, [], f"{node} logged errors")
            self.assertTrue(rosnode.rosnode_ping(node, max_count=1), f"{node} is not up")
        self.assertEqual(handles.messages, [], "/ComauHandles published without a simulator")
        self.assertEqual(prox.messages, [], "/prox_data published without a simulator")

    def test_an_unusable_parameter_exits_2_naming_it(self):
        run = subprocess.run(["rosrun", PKG, "proxSensors", "__name:=proxSensors_bad_rate",
                              "_rate:=-5"], capture_output=True, text=True, timeout=60)
        self.assertEqual(run.returncode, 2, run.stdout + run.stderr)
        self.assertIn("~rate", run.stdout + run.stderr)


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_thesis_nodes_waiting", ThesisNodesWaiting)

#!/usr/bin/python3
"""rospy's own shutdown of the simulator (``rosnode kill /vrep``: the node's XML-RPC
``shutdown``) stops it as SIGINT does (``ros/node/stop.py``), not through rospy's clean-up
racing the stop: it logs ``epuck_sim stops (shutdown request at t=… s)``, exits by itself with
status 0 and no traceback, and the master forgets it. The waits are liveness guards only."""
import os
import signal
import subprocess
import tempfile
import time
import unittest

import rosgraph
import rospy
import rostest
from rosgraph_msgs.msg import Clock

from sim_test_helpers import PKG, master_knows, wait_for_message

LIVENESS_S = 120.0    # a guard against a hang, far beyond what a stop takes
STOPPED = "epuck_sim stops (shutdown request at t="


class ShutdownRequest(unittest.TestCase):
    def test_rosnode_kill_stops_it_as_a_signal_does(self):
        rospy.init_node("test_shutdown_request", disable_signals=True)
        with tempfile.TemporaryDirectory(prefix="test_shutdown_request_") as tmp:
            log_path = os.path.join(tmp, "simulator.log")
            with open(log_path, "w") as log:
                sim = subprocess.Popen(["rosrun", PKG, "epuck_sim", "_n:=2"], stdout=log,
                                       stderr=subprocess.STDOUT, start_new_session=True)
            try:
                wait_for_message("/clock", Clock, timeout_s=LIVENESS_S)
                # rosnode takes a call the node ends before answering as done
                subprocess.run(["rosnode", "kill", "/vrep"], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL, timeout=LIVENESS_S, check=True)
                sim.wait(timeout=LIVENESS_S)
            finally:
                if sim.poll() is None:             # hung: only what this test started
                    os.killpg(sim.pid, signal.SIGKILL)
                    sim.wait()
            with open(log_path) as f:
                output = f.read()
        self.assertEqual(sim.returncode, 0, output[-3000:])
        self.assertIn(STOPPED, output)
        self.assertNotIn("Traceback", output)
        master = rosgraph.Master("/test_shutdown_request")
        deadline = time.monotonic() + LIVENESS_S
        while master_knows(master) and time.monotonic() < deadline:
            time.sleep(0.1)
        self.assertFalse(master_knows(master), "the master still knows /vrep")


if __name__ == "__main__":
    rostest.rosrun(PKG, "shutdown_request", ShutdownRequest)

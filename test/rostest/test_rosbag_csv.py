#!/usr/bin/python3
"""A run recorded with ``rosbag record`` becomes CSV with ``rostopic echo -p -b``."""
import csv
import io
import os
import subprocess
import tempfile
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock

from epuck_vrep_compat.epuck import paper_robot as paper
from sim_test_helpers import PKG, wait_for_message


class RosbagCsv(unittest.TestCase):
    def test_record_and_convert(self):
        rospy.init_node("test_rosbag_csv")
        wait_for_message("/clock", Clock)
        tmp = tempfile.mkdtemp()
        bag = os.path.join(tmp, "run.bag")
        topics = ["/ePuck0/imu", "/ePuck0/proximity0", "/ePuck1/proximity7", "/tf"]
        subprocess.run(["rosbag", "record", "-O", bag, "--duration=4"] + topics,
                       check=True, capture_output=True, timeout=90)
        info = subprocess.run(["rosbag", "info", bag], check=True, capture_output=True,
                              text=True).stdout
        for topic in topics:
            self.assertIn(topic, info)
        imu = self._csv(bag, "/ePuck0/imu")
        self.assertIn("field.linear_acceleration.z", imu[0])
        self.assertGreaterEqual(len(imu), 40)       # ~4 s at 20 Hz
        z = [float(r["field.linear_acceleration.z"]) for r in imu]
        # g plus the default bias of the paper's real robot (Table 1's z mean)
        self.assertAlmostEqual(sum(z) / len(z), paper.TABLE1_REAL_MEAN_M_S2[2], delta=0.05)
        ranges = self._csv(bag, "/ePuck1/proximity7")
        self.assertTrue(all(0.0015 - 1e-6 <= float(r["field.range"]) <= 0.05 + 1e-6
                            for r in ranges))   # float32 field
        self.assertEqual(ranges[0]["field.header.frame_id"], "ePuck1/base_prox7")

    def _csv(self, bag, topic):
        out = subprocess.run(["rostopic", "echo", "-p", "-b", bag, topic], check=True,
                             capture_output=True, text=True, timeout=60).stdout
        return list(csv.DictReader(io.StringIO(out)))


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_rosbag_csv", RosbagCsv)

#!/usr/bin/python3
"""The paper's scenarios through ROS topics, default noise (the paper's real e-puck).

rest (paper_rest.launch): 20 s standing in open space; 8 sensors' error rate and the IMU's bias.
straight (paper_straight.launch): 20 s of simulated time at 4 cm/s in open space; the IR
readings of all 8 sensors (default p = 0.16 each, 3 200 readings, SE 0.0065) and Table 1's real
row on /ePuck0/imu (400 samples: means within 0.05 m/s², SDs within 10 %).
wall (paper_wall.launch): the wall 0.5 cm ahead is seen by sensors 0, 1, 6, 7 at first and by
none of them once the robot has reversed for 3 s."""
import math

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import Imu, Range

from sim_test_helpers import PKG, Collector, SimTestCase, unpause_when_subscribed

TABLE1_MEAN = np.array([-0.05254, -0.26087, 9.68479])
TABLE1_SD = np.array([0.03559, 0.03079, 0.04930])


def window(messages, t0, t1):
    return [m for m in messages if t0 <= m.header.stamp.to_sec() < t1]


class PaperScenario(SimTestCase):
    NODE = "test_paper_scenarios"

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.ir = [Collector(f"/ePuck0/proximity{k}", Range) for k in range(8)]
        cls.imu = Collector("/ePuck0/imu", Imu)
        unpause_when_subscribed(cls.ir + [cls.imu])

    def test_scenario(self):
        getattr(self, "check_" + rospy.get_param("~scenario"))()
        self.assertEqual(self.guard.errors, [])

    def check_straight(self):
        # The steady part of the 20 s drive: from 0.5 s after its start to before its stop
        # (stamps: simulated time; the drive starts with the first /clock).
        imu = window(self.imu.wait(460, 600.0), 0.5, 19.95)
        accel = np.array([[m.linear_acceleration.x, m.linear_acceleration.y,
                           m.linear_acceleration.z] for m in imu])
        self.assertGreaterEqual(len(accel), 380)  # the paper's 380
        np.testing.assert_array_less(np.abs(accel.mean(axis=0) - TABLE1_MEAN), 0.05)
        np.testing.assert_array_less(np.abs(accel.std(axis=0, ddof=1) / TABLE1_SD - 1), 0.10)
        ranges = np.array([m.range for c in self.ir for m in window(c.wait(460, 600.0), 0.6, 22)])
        wrong = (ranges < 0.05 - 1e-6).mean()
        self.assertLess(abs(wrong - 0.16), 3 * math.sqrt(0.16 * 0.84 / ranges.size), wrong)

    def check_rest(self):
        # Standing in open space: every sensor's errors (p = 0.16) and the accelerometer's
        # bias (Table 1's means) with only the sensor's own spread (no motion).
        imu = window(self.imu.wait(420, 600.0), 0.0, 20.0)
        accel = np.array([[m.linear_acceleration.x, m.linear_acceleration.y,
                           m.linear_acceleration.z] for m in imu])
        self.assertGreaterEqual(len(accel), 390)
        se = TABLE1_SD / math.sqrt(len(accel))
        np.testing.assert_array_less(np.abs(accel.mean(axis=0) - TABLE1_MEAN), 4 * se)
        self.assertLess(accel[:, 0].std(ddof=1), TABLE1_SD[0])
        ranges = np.array([m.range for c in self.ir for m in window(c.wait(420, 600.0), 0, 20)])
        wrong = (ranges < 0.05 - 1e-6).mean()
        self.assertLess(abs(wrong - 0.16), 3 * math.sqrt(0.16 * 0.84 / ranges.size), wrong)

    def check_wall(self):
        ir = {k: self.ir[k].wait(140, 600.0) for k in (0, 1, 6, 7)}
        for k, messages in ir.items():
            first = [m.range for m in window(messages, 0.0, 0.5)]
            late = [m.range for m in window(messages, 5.0, 7.0)]
            self.assertLess(np.median(first), 0.03, f"sensor {k} should see the wall")
            self.assertEqual(np.median(late), np.float32(0.05), f"sensor {k} out of range")
        # The first three readings (0.15 s, under 4 mm of reversing): the wall 0.5 cm ahead.
        front = [m.range for m in ir[0][:3]]
        self.assertAlmostEqual(float(np.median(front)), 0.0065, delta=0.002)


if __name__ == "__main__":
    rostest.rosrun(PKG, "paper_scenarios", PaperScenario)

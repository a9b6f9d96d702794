#!/usr/bin/python3
"""fit_noise on a bag recorded through ROS from the simulator, which runs the rest scenario
with the non-default noise of test/worlds/noise_nondefault.yaml (the noise_file launch
argument): every fitted parameter recovered within the standard errors fit_noise writes.

36 estimates are checked at once, so the bound is family-wise rather than tuned to a seed:
every estimate within 4 SE (a correct fit fails that with probability 36 x 6.3e-5 = 0.2 %),
and at least 33 of the 36 within 3 SE (a correct fit has 35.9 on average; 4 or more outside
3 SE has probability 8e-6). A fit that misses a parameter by a few SE fails both."""
import os
import subprocess
import tempfile
import threading
import unittest

import rosbag
import rospy
import rostest
import yaml
from sensor_msgs.msg import Imu, Range

from sim_test_helpers import PKG, unpause_when_subscribed, wait_sim_time

# The simulated seconds recorded: a fixed window, so the sample is the same whatever the
# moment this node connects (it must connect before the window opens).
WINDOW_S = (3.0, 33.0)
ROBOT = "ePuck0"


class FitNoiseRecorded(unittest.TestCase):
    def test_fit_recovers_the_simulators_parameters(self):
        rospy.init_node("test_fit_noise_recorded")
        truth = yaml.safe_load(open(rospy.get_param("~noise_file")))
        out = tempfile.mkdtemp(prefix="fit_noise_")
        bag_path = os.path.join(out, "rest.bag")
        lock = threading.Lock()
        first = []
        with rosbag.Bag(bag_path, "w") as bag:
            def write(msg, topic):
                with lock:
                    if not first:
                        first.append(msg.header.stamp.to_sec())
                    if WINDOW_S[0] <= msg.header.stamp.to_sec() < WINDOW_S[1]:
                        bag.write(topic, msg, msg.header.stamp)
            topics = [(f"/{ROBOT}/proximity{k}", Range) for k in range(8)]
            subs = [rospy.Subscriber(t, c, write, t, queue_size=1000)
                    for t, c in topics + [(f"/{ROBOT}/imu", Imu)]]
            unpause_when_subscribed(subs)
            wait_sim_time(WINDOW_S[1] + 0.5, timeout_s=600.0)
            for s in subs:
                s.unregister()
            rospy.sleep(0.2)
        self.assertLess(first[0], WINDOW_S[0], "connected after the window opened")
        out_file = os.path.join(out, "fit.yaml")
        proc = subprocess.run(["rosrun", PKG, "fit_noise", bag_path, "--scenario", "rest",
                               "-o", out_file], capture_output=True, text=True, timeout=120)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        fit = yaml.safe_load(open(out_file))["fit"]
        self.z_scores = {}
        ir = truth["ir_noise"]
        for k in range(8):
            f = fit["ir"][f"proximity{k}"]
            self.assertEqual(f["samples"], 600)
            self.assert_within(f["probability"], ir["probability"][k], f"p{k}")
            self.assert_within(f["mean_m"], ir["mean_m"], f"mean{k}")
            self.assert_within(f["stddev_m"], ir["stddev_m"], f"sd{k}")
        imu = truth["imu_noise"]
        for sensor, unit in (("accel", "m_s2"), ("gyro", "rad_s")):
            for axis in range(3):
                self.assert_within(fit[sensor]["bias"][axis], imu[f"{sensor}_bias_{unit}"][axis],
                                   f"{sensor} bias {axis}")
                self.assert_within(fit[sensor]["stddev"][axis],
                                   imu[f"{sensor}_stddev_{unit}"][axis], f"{sensor} sd {axis}")
        self.assertEqual(len(self.z_scores), 36)
        outside = {what: z for what, z in self.z_scores.items() if z >= 3.0}
        self.assertLessEqual(len(outside), 3, f"more than 3 of 36 beyond 3 SE: {outside}")

    def assert_within(self, estimate, truth, what):
        self.assertGreater(estimate["se"], 0.0, what)
        z = abs(estimate["value"] - truth) / estimate["se"]
        self.z_scores[what] = z
        self.assertLess(z, 4.0, f"{what}: {estimate} against {truth} ({z:.2f} SE)")


if __name__ == "__main__":
    rostest.rosrun(PKG, "fit_noise_recorded", FitNoiseRecorded)

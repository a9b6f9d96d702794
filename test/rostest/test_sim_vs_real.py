#!/usr/bin/python3
"""sim_vs_real end to end on a simulator-made "real" bag: 6 s of the straight scenario (1 s
standing, then 4 cm/s) made by the simulator's core with known, non-default noise, written in
the epuck_driver profile's names. The report exists, its fitted-noise table holds fit_noise's
values, its PNGs are 800 x 600, the simulated run with the fitted noise shows the bag's
accelerometer bias, and the bag's cmd_vel was replayed (the noise-free run's start jolt)."""
import os
import re
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import rosbag
import rostest
import yaml
from matplotlib.image import imread

from sim_test_helpers import PKG
from repo import REPO  # test/ on the path: sim_test_helpers  # isort: skip

sys.path.insert(0, os.path.join(REPO, "test", "unit"))
from test_fit_noise import TRUE, make_bag  # noqa: E402  (the unit tier's bag maker)


class SimVsReal(unittest.TestCase):
    def test_report_end_to_end(self):
        out = tempfile.mkdtemp(prefix="sim_vs_real_")
        bag = os.path.join(out, "real.bag")
        make_bag(bag, "epuck_robot_0", "accel", 0.04, 120)          # 6 s, moving from 1 s
        proc = subprocess.run(["rosrun", PKG, "sim_vs_real", bag, "--scenario", "straight",
                               "-o", os.path.join(out, "report")],
                              capture_output=True, text=True, timeout=600)
        self.assertEqual(proc.returncode, 0, proc.stderr[-3000:])
        self.assertIn("sim_fitted:   5.0 / 6.0 s simulated", proc.stderr)   # progress
        report_dir = os.path.join(out, "report")
        text = open(os.path.join(report_dir, "report.md")).read()
        noise = yaml.safe_load(open(os.path.join(report_dir, "fitted_noise.yaml")))
        bias_x = noise["fit"]["accel"]["bias"][0]["value"]
        self.assertIn(f"| accel x bias [m/s²] | {bias_x:.6f} |", text)
        p0 = noise["fit"]["ir"]["proximity0"]["probability"]["value"]
        self.assertIn(f"| proximity0 probability | {p0:.6f} |", text)
        for source in ("real", "sim_fitted", "sim_ideal"):
            self.assertRegex(text, rf"\| {source} z \| 9\.\d+")
        for png in ("accel.png", "proximity.png", "ir_errors.png"):
            self.assertIn(f"]({png})", text)
            image = imread(os.path.join(report_dir, png))
            self.assertEqual(image.shape[:2], (600, 800), png)
            self.assertGreater(float(np.std(image)), 0.01, f"{png} is blank")
        # The fitted simulation's mean x acceleration carries the bag's bias; ideal has none.
        means = {m.group(1): float(m.group(2)) for m in re.finditer(
            r"\| (\w+) x \| [-\d.]+ \| [-\d.]+ \| [-\d.]+ \| ([-\d.]+) \|", text)}
        self.assertAlmostEqual(means["sim_fitted"], TRUE.accel_bias_m_s2[0], delta=0.02)
        self.assertAlmostEqual(means["sim_ideal"], 0.0, delta=1e-6)
        # Replayed: 0.04 m/s reached within one 50 ms step, about 1 s in (the bag's time).
        with rosbag.Bag(os.path.join(report_dir, "sim_ideal.bag")) as b:
            jolt = [(m.header.stamp.to_sec(), m.linear_acceleration.x)
                    for _, m, _ in b.read_messages(topics=["/ePuck0/imu"])
                    if abs(m.linear_acceleration.x) > 0.1]
        self.assertEqual(len(jolt), 1, jolt)
        self.assertAlmostEqual(jolt[0][1], 0.8, delta=0.01)
        self.assertAlmostEqual(jolt[0][0], 1.0, delta=0.2)

    def test_bag_lacking_topics_exits_1(self):
        out = tempfile.mkdtemp(prefix="sim_vs_real_")
        bag = os.path.join(out, "broken.bag")
        open(bag, "wb").close()
        proc = subprocess.run(["rosrun", PKG, "sim_vs_real", bag, "--scenario", "wall"],
                              capture_output=True, text=True, timeout=120)
        self.assertEqual(proc.returncode, 1)
        self.assertIn("cannot read bag", proc.stderr)


if __name__ == "__main__":
    rostest.rosrun(PKG, "sim_vs_real", SimVsReal)

#!/usr/bin/python3
"""Issue 26: the same walk gives the same separations at rtf 1 and flat out, when the
simulator and the supervisor run in lock-step (merlin_safety.launch lockstep:=true), and the
same again when the paused simulation is advanced a step at a time by ``/vrep/step``.

Each rate is one run of safety_lockstep_run.launch (merlin_safety.launch on ground truth, a
seeded walk into the IRB 140, lockstep_recorder triggering every step, or calling /vrep/step,
and recording the operator's true separation after it), on a ROS master of its own. The series,
keyed by their simulated-time stamps, and the supervisor's scales in order must be equal, bit
for bit."""
import csv
import os
import signal
import subprocess
import tempfile
import unittest

import rospkg
import rospy
import rostest

from epuck_vrep_compat.experiment.isolation import free_port
from sim_test_helpers import PKG

HERE = os.path.dirname(os.path.abspath(__file__))
DURATION_S = 12.0


def run(rtf, folder, by_step_service=False):
    """One run at ``rtf``: ({stamp_ns: (separation, link)}, [scales in order])."""
    name = "step_service" if by_step_service else f"rtf_{rtf}"
    out = os.path.join(folder, f"{name}.csv")
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}",
               ROS_HOME=os.path.join(folder, f"home_{name}"))
    proc = subprocess.Popen(
        ["roslaunch", "-p", str(port), os.path.join(HERE, "safety_lockstep_run.launch"),
         f"rtf:={rtf}", f"out:={out}", f"duration:={DURATION_S}",
         f"by_step_service:={str(by_step_service).lower()}"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        start_new_session=True)
    try:            # the recorder is required: its end ends the run (rostest's limit guards hangs)
        log, _ = proc.communicate()
    finally:
        if proc.poll() is None:             # only what this run started: its process group
            os.killpg(proc.pid, signal.SIGINT)
            proc.wait(30)
    with open(out) as f:
        rows = {int(r["stamp_ns"]): (float(r["separation_m"]), r["link"])
                for r in csv.DictReader(f)}
    with open(out + ".scales") as f:
        scales = [float(line) for line in f]
    return rows, scales, log


class SafetyLockstep(unittest.TestCase):
    def test_the_same_walk_gives_the_same_separations_at_rtf_1_and_flat_out(self):
        rospy.init_node("test_safety_lockstep")
        self.assertTrue(rospkg.RosPack().get_path(PKG))
        with tempfile.TemporaryDirectory() as folder:
            real, real_scales, real_log = run("1.0", folder)
            fast, fast_scales, fast_log = run("0", folder)
            stepped, stepped_scales, stepped_log = run("0", folder, by_step_service=True)
        for log in (real_log, fast_log, stepped_log):
            self.assertNotIn("lockstep: no speed scale", log)     # no late step
        steps = int(round(DURATION_S / 0.05))
        self.assertEqual(sorted(real), [k * 50_000_000 for k in range(1, steps + 1)])
        self.assertEqual(real, fast)                              # by stamp, bit for bit
        self.assertEqual(real_scales, fast_scales)
        # /vrep/step waits for the supervisor's answer to each step as the loop does
        self.assertEqual(real, stepped)
        self.assertEqual(real_scales, stepped_scales)
        # the walk came to the arm and the supervisor acted: slowed, then stopped it
        self.assertLess(min(d for d, _ in real.values()), 0.5)
        self.assertIn(0.0, real_scales[1:])
        self.assertTrue(any(0.0 < s < 1.0 for s in real_scales))


if __name__ == "__main__":
    rostest.rosrun(PKG, "safety_lockstep", SafetyLockstep)

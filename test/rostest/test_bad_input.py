#!/usr/bin/python3
"""Bad input: refused with a clear message, the simulator keeps running, nothing non-finite."""
import math
import os
import subprocess
import tempfile
import time

import rospkg
import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, Range
from std_msgs.msg import String, UInt8MultiArray

from epuck_vrep_compat.srv import StepSimulation
from sim_test_helpers import PKG, Collector, SimTestCase, wait_sim_time


def finite_odometry(msg):
    p, q, t = msg.pose.pose.position, msg.pose.pose.orientation, msg.twist.twist
    return all(math.isfinite(v) for v in (p.x, p.y, p.z, q.x, q.y, q.z, q.w, t.linear.x,
                                           t.angular.z))


class BadInput(SimTestCase):
    NODE = "test_bad_input"

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.truth = Collector("/ePuck0/ground_truth", Odometry)
        cls.truth.wait(1, timeout_s=30)

    def _publish_when_connected(self, pub, msg):
        deadline = time.monotonic() + 10
        while pub.get_num_connections() == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        pub.publish(msg)

    def _assert_alive_and_finite(self):
        self.truth.clear()
        msgs = self.truth.wait(5, timeout_s=20)
        self.assertTrue(all(finite_odometry(m) for m in msgs))
        ranges = Collector("/ePuck0/proximity0", Range).wait(3)
        self.assertTrue(all(m.min_range <= m.range <= m.max_range for m in ranges))
        imu = Collector("/ePuck0/imu", Imu).wait(3)
        self.assertTrue(all(math.isfinite(m.linear_acceleration.z) for m in imu))

    def test_non_finite_and_huge_cmd_vel(self):
        pub = rospy.Publisher("/ePuck0/cmd_vel", Twist, queue_size=10)
        for v, w in ((math.nan, 0.0), (0.0, math.inf), (-math.inf, math.nan), (1e308, -1e308),
                     (-0.0, 5e-324)):
            cmd = Twist()
            cmd.linear.x, cmd.angular.z = v, w
            self._publish_when_connected(pub, cmd)
            wait_sim_time(0.2)
        self._assert_alive_and_finite()
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline and not any("non-finite" in w
                                                      for w in self.guard.warnings):
            time.sleep(0.1)
        self.assertTrue(any("non-finite" in w for w in self.guard.warnings),
                        self.guard.warnings)

    def test_wrong_led_arrays(self):
        pub = rospy.Publisher("/ePuck1/cmd_led", UInt8MultiArray, queue_size=10)
        self._publish_when_connected(pub, UInt8MultiArray(data=bytes(40)))
        wait_sim_time(0.3)
        self._publish_when_connected(pub, UInt8MultiArray(data=b""))
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline and not any("cmd_led" in w
                                                      for w in self.guard.warnings):
            time.sleep(0.1)
        self.assertTrue(any("cmd_led" in w for w in self.guard.warnings), self.guard.warnings)
        self._assert_alive_and_finite()

    def test_wrong_message_type_is_refused_by_ros(self):
        pub = rospy.Publisher("/ePuck0/cmd_vel", String, queue_size=1)
        for _ in range(5):
            pub.publish(String(data="forward"))
            time.sleep(0.1)
        self.assertEqual(pub.get_num_connections(), 0)
        pub.unregister()
        self._assert_alive_and_finite()

    def test_step_service_refuses_while_running(self):
        step = rospy.ServiceProxy("/vrep/step", StepSimulation, persistent=True)
        for _ in range(20):
            self.assertFalse(step(3).success)
        self._assert_alive_and_finite()

    def test_unusable_configuration_exits_non_zero_naming_the_parameter(self):
        with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
            f.write("obstacles:\n  - {shape: cone, position_m: [0, 0]}\n")
            malformed = f.name
        cell = os.path.join(rospkg.RosPack().get_path(PKG), "worlds", "merlin_safety.yaml")
        cases = [
            (["_world:=/nonexistent/scene.yaml"], "cannot read scene file"),
            ([f"_world:={malformed}"], "obstacles[0].shape"),
            (["_ir_noise/stddev_m:=-0.1"], "~ir_noise/stddev_m"),
            (["_imu_noise/accel_stddev_m_s2:=-1.0"], "~imu_noise/accel_stddev_m_s2"),
            (["_profile:=webots"], "~profile"),
            (["_n:=5000"], "~n"),
            (["_rtf:=-1.0"], "~rtf"),
            (["_noise_preset:=real"], "~noise_preset"),
            (["_noise_file:=/nonexistent/noise.yaml"], "~noise_file"),
            ([f"_noise_file:={malformed}"], "noise file must be a mapping"),
            (['_robots:={ePuck9: {ir_noise: {probability: 0.5}}}'], "~robots/ePuck9"),
            ([f"_world:={cell}", "_operator_walk_seed:=-2"], "'~operator_walk_seed' must be"),
            ([f"_world:={cell}", "_operator_walk_seed:=abc"], "'~operator_walk_seed' must be"),
            ([f"_world:={cell}", "_operator_walk_seed:=1", "_operator_trace:=a.csv"],
             "give one, not both"),
            ([f"_world:={cell}", "_operator_trace:=/nonexistent/walk.csv"],
             "'~operator_trace': operator trace '/nonexistent/walk.csv': cannot read it"),
            ([f"_world:={cell}", f"_operator_trace:={malformed}"], "row 1: the header must be"),
            (["_operator_walk_seed:=3"], "has no cell operator"),
            ([f"_world:={cell}", "_lockstep_timeout_s:=-1.0"], "'~lockstep_timeout_s'"),
        ]
        try:
            for k, (args, expected) in enumerate(cases):
                proc = subprocess.run(
                    ["rosrun", PKG, "epuck_sim", f"__name:=bad_config_{k}"] + args,
                    capture_output=True, text=True, timeout=60)
                output = proc.stdout + proc.stderr
                self.assertNotEqual(proc.returncode, 0, f"{args} started: {output}")
                self.assertIn(expected, output, f"{args}: {output}")
        finally:
            os.unlink(malformed)
        self._assert_alive_and_finite()

    def test_zz_no_errors_from_the_simulator(self):
        sim_errors = [e for e in self.guard.errors if e.startswith("/vrep")]
        self.assertEqual(sim_errors, [])


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_bad_input", BadInput)

#!/usr/bin/python3
"""/vrep/rewind (issue 26): the simulation back to time 0 as if launched again with a seed.
Rewound to the launch's seed, the same steps give the same messages to the last bit (joint
states and the noisy laser, stamped from 0 again, the operator where his walk puts him); rewound to
another seed, the operator walks another walk and the laser's noise differs; a bad request is
refused and changes nothing."""
import time

import rospy
import rostest
from sensor_msgs.msg import JointState, LaserScan

from epuck_vrep_compat.compat.topics import (
    CELL_LASER_TOPIC, JOINT_STATES_TOPIC, NODE_NAMESPACE, REWIND_SERVICE)
from epuck_vrep_compat.srv import Rewind, StepSimulation
from sim_test_helpers import Collector, SimTestCase, call, handle

STEPS = 30          # 1.5 s: 16 scans (the one taken at the start, then every other step)
SCANS = STEPS // 2 + 1


class RewindTest(SimTestCase):
    NODE = "test_rewind"
    SERVICES = (REWIND_SERVICE,)

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.rewind = rospy.ServiceProxy(REWIND_SERVICE, Rewind)
        cls.step = rospy.ServiceProxy(NODE_NAMESPACE + "step", StepSimulation)
        cls.topics = [Collector(JOINT_STATES_TOPIC.format(robot="IRB140"), JointState),
                      Collector(NODE_NAMESPACE + CELL_LASER_TOPIC, LaserScan)]
        deadline = time.monotonic() + 30
        while any(c.get_num_connections() == 0 for c in cls.topics):
            assert time.monotonic() < deadline, "not connected to the cell's topics"
            time.sleep(0.05)
        cls.operator = handle("Bill")

    def steps(self):
        """STEPS steps from where the simulation is: every message and the operator's pose."""
        for c in self.topics:
            c.clear()
        self.assertTrue(self.step(steps=STEPS).success)
        joints, scans = (c.wait(n) for c, n in zip(self.topics, (STEPS, SCANS)))
        pose = call("simRosGetObjectPose", handle=self.operator, relativeToObjectHandle=-1)
        p = pose.pose.pose.position
        return {"joints": [(m.header.stamp.to_nsec(), m.position, m.velocity) for m in joints],
                "scans": [(m.header.stamp.to_nsec(), m.ranges) for m in scans],
                "operator": (p.x, p.y)}

    def test_1_rewound_to_its_seed_it_steps_as_launched(self):
        first = self.steps()
        self.assertEqual(first["joints"][0][0], 50_000_000)      # the first step's stamp
        self.assertTrue(self.rewind(seed=0, operator_walk_seed=0).success)
        again = self.steps()
        for part in first:
            self.assertEqual(first[part], again[part], part)

    def test_2_another_seed_another_walk_and_noise(self):
        self.assertTrue(self.rewind(seed=0, operator_walk_seed=0).success)
        zero = self.steps()
        self.assertTrue(self.rewind(seed=5, operator_walk_seed=5).success)
        five = self.steps()
        self.assertEqual([j[0] for j in five["joints"]], [j[0] for j in zero["joints"]])
        self.assertNotEqual(five["operator"], zero["operator"])
        self.assertNotEqual(five["scans"], zero["scans"])

    def test_3_a_bad_request_is_refused_and_changes_nothing(self):
        self.assertTrue(self.rewind(seed=0, operator_walk_seed=0).success)
        before = self.steps()
        for bad in ({"seed": -1, "operator_walk_seed": 0}, {"seed": 1, "operator_walk_seed": -2}):
            answer = self.rewind(**bad)
            self.assertFalse(answer.success)
            self.assertIn("must be", answer.message)
        self.assertTrue(self.rewind(seed=0, operator_walk_seed=0).success)
        self.assertEqual(self.steps(), before)

    def test_9_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun("epuck_vrep_compat", "test_rewind", RewindTest)

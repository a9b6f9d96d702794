#!/usr/bin/python3
"""The README's first walk-through, run for real, and the docs' names on a live master.

docs_walkthrough.test starts the simulator as the walk-through does; this client runs each of
the walk-through's command lines (after waiting for every topic and service it names) and
checks that each succeeds, and that every topic and service the README and docs/ name for an
e-puck simulator of the vrep profile (two robots) exists, with the type ``rostopic pub`` gives.
Names of other launches (the cell, the driver profiles, more robots) are printed, not checked.
"""
import math
import os
import re
import subprocess
import sys
import tempfile
import time

import rosgraph.masterapi
import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock

from sim_test_helpers import PKG, Collector, SimTestCase, wait_sim_time
from repo import REPO  # test/ on the path: sim_test_helpers  # isort: skip

sys.path.insert(0, os.path.join(REPO, "tools"))
import doc_commands as docs  # noqa: E402

ROBOTS = 2                   # n:=2, as the walk-through starts it
COMMAND_TIMEOUT_S = 60.0
NAMES_TIMEOUT_S = 60.0


def in_this_simulator(name):
    """Whether a name belongs to the simulator this test starts: named after an e-puck
    simulator of the vrep profile was started on its page, or before any, and of a robot
    that two robots include."""
    launch = docs.launch_of(name.command.context) if name.command.context else None
    if launch and ("epucks.launch" not in docs.includes(launch.file)
                   or launch.args.get("profile", "vrep") != "vrep"):
        return False
    robot = re.match(r"^/ePuck(\d+)/", name.name)
    return robot is None or int(robot.group(1)) < ROBOTS


def master_state():
    """(topics published or subscribed, services, topic -> type) of the live master."""
    master = rosgraph.masterapi.Master(rospy.get_name())
    pubs, subs, services = master.getSystemState()
    topics = {t for t, _ in pubs} | {t for t, _ in subs}
    return topics, {s for s, _ in services}, dict(master.getTopicTypes())


def problem(name, state):
    """Why a name is not on the master (None when it is). A topic may be written with a field
    of it (``rostopic echo /ePuck0/imu/linear_acceleration``)."""
    topics, services, types = state
    if name.kind == "service":
        return None if name.name in services else f"no service {name.name}"
    parts = name.name.split("/")
    for end in range(len(parts), 1, -1):
        topic = "/".join(parts[:end])
        if topic in topics:
            if name.msg_type and types.get(topic) != name.msg_type:
                return f"{topic} is {types.get(topic)}, not {name.msg_type}"
            return None
    return f"no topic {name.name}"


def wait_for_names(names, timeout_s=NAMES_TIMEOUT_S):
    """The names' problems once every name is on the master, or when the time is up."""
    deadline = time.monotonic() + timeout_s
    while True:
        state = master_state()
        problems = [f"{n.command.page}:{n.command.line}: {p}" for n in names
                    for p in [problem(n, state)] if p]
        if not problems or time.monotonic() > deadline:
            return problems
        time.sleep(0.2)


def position(odometry):
    p = odometry.pose.pose.position
    return p.x, p.y


class DocsWalkthrough(SimTestCase):
    NODE = "test_docs_walkthrough"
    FIRST_MESSAGE = ("/clock", Clock)

    def test_every_name_the_docs_give_this_simulator_exists(self):
        names = [n for c in docs.all_commands(REPO) for n in docs.names_of(c)]
        live = [n for n in names if in_this_simulator(n)]
        others = sorted({n.name for n in names if not in_this_simulator(n)})
        print("names of other launches, not checked live:", " ".join(others))
        self.assertGreater(len(live), 10)
        self.assertEqual(wait_for_names(live), [])

    def test_the_walkthrough_runs(self):
        _, lines = docs.walkthrough(REPO)
        path = Collector("/ePuck0/ground_truth", Odometry)
        start = position(path.wait(1)[0])
        with tempfile.TemporaryDirectory() as cwd:
            for commands in lines:
                self.run_line(commands, cwd)
        moved = max(math.dist(start, position(m)) for m in path.messages)
        self.assertGreater(moved, 0.01, "ePuck0 never moved")
        # the last command stops it: it stands still from then on
        wait_sim_time(0.5)
        before = position(path.latest())
        wait_sim_time(1.0)
        self.assertLess(math.dist(before, position(path.latest())), 1e-3)
        self.assertEqual(self.guard.errors, [])

    def run_line(self, commands, cwd):
        """Run one command line of the walk-through once what it names is there."""
        where = commands[0].where()
        self.assertEqual(wait_for_names([n for c in commands for n in docs.names_of(c)]), [],
                         where)
        result = subprocess.run(["bash", "-o", "pipefail", "-c", commands[0].text], cwd=cwd,
                                capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S)
        output = result.stdout + result.stderr
        self.assertEqual(result.returncode, 0, f"{where}\n{output}")
        if any(c.words[:2] == ["rostopic", "echo"] for c in commands):
            self.assertTrue(result.stdout.strip(), f"{where}: printed nothing")
        self.assertNotIn("success: False", result.stdout, where)


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_docs_walkthrough", DocsWalkthrough)

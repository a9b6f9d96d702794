"""The ``experiment_probe`` node: starts a run, records it, and ends it.

Started (paused) by the run's launch file beside the simulator and the user's code. It waits
for the simulator's ``/vrep/unpause`` service and for a publisher on every topic it records
(in a run with a bag, for ``rosbag record`` to subscribe to each too: ``~recorder``), gives
the user's nodes ``start_grace_s`` to subscribe (not between the walks of one launch when
every node was reset in place: :mod:`probe_walks`), then starts the simulation: ``free``,
at whatever real-time factor the simulator was given (the runner gives ``rtf:=0``), or
``lockstep``, V-REP's synchronous mode: one step, then wait until every ``wait_for`` topic
has published once (or ``step_timeout_s`` of wall time passed: a late step, counted, and
added to the steps other nodes took without waiting, ``ros/common/late_steps.py``; with
``skip_gone``, a topic whose publishers have all gone is not waited for). In lock-step an
answer is a message that came after the step's trigger (a latched one sent before the start
answers no step), and a message without a stamp is recorded at the time of the step during
which it came (the simulator holds that step until the next trigger), even when that step's
``/clock`` reaches the probe after it.
The simulator gets an answer on its own connection, which may be behind the probe's: for a
robot's ``cmd_vel`` it waits for the answer itself before the step the trigger asks for (the
runner sets ``epucks.launch``'s ``lockstep_cmd_vel``, ``launch_files.cmd_vel_lockstep``);
for other topics ``settle_s`` before each trigger gives it the time.
It records every message of the topics matching ``~topics`` (glob patterns) as numeric
columns, and once the simulated time reaches ``~duration_s`` writes the recording (npz), the
world's scene file and a status file beside it, then exits: the launch marks it required, so
roslaunch ends the run. Exit status 0 done, 2 the run never started (the status says why).
"""
import fnmatch
import json
import os
import sys
import threading
import time

import rosgraph
import rospy
from rosgraph_msgs.msg import Clock
from roslib.message import get_message_class
from std_srvs.srv import Empty

from epuck_vrep_compat.compat.topics import NODE_NAMESPACE, UNPAUSE_SERVICE
from epuck_vrep_compat.experiment import flatten, metrics, probe_walks
from epuck_vrep_compat.ros.common.late_steps import total as nodes_late_steps

START_TIMEOUT_S = 60.0
GONE_POLL_S = 0.05     # how often a step's wait looks for wait_for topics left silent
CLOCK_WAIT_S = 1.0     # wall time an unstamped message waits for its step's /clock


class Probe:
    """The run's recording and its pace (see the module's docstring)."""

    def __init__(self, settings):
        self.duration_s = float(settings["duration_s"])
        self.out = settings["out"]
        self.patterns = list(settings.get("topics", []))
        self.recorder = settings.get("recorder", "")     # a run with a bag: rosbag's node
        self.pace = settings.get("pace", {"mode": "free"})
        self.lock = threading.Condition()
        self.clock = 0.0
        self.columns = {}                # topic -> flatten.Columns
        self.counts = {}                 # wait_for's topics -> messages received
        self.late_steps = 0              # steps the probe took without an answer
        self.late_before = 0             # every node's late steps when the run started
        self.triggered = self.clocks = 0         # lock-step: steps triggered, their /clock seen
        self.times = {"probe": time.time()}       # wall clock of each phase, for the row
        self.subs = []
        self.by_topic = {}               # wait_for's topics -> their subscriber
        self.ready_counts = None         # counts when the launch's first walk started

    # --- callbacks -------------------------------------------------------------------------
    def on_clock(self, msg):
        with self.lock:
            if msg.clock.to_sec() > self.clock:
                self.clocks += 1
            self.clock = msg.clock.to_sec()
            self.lock.notify_all()

    def on_message(self, msg, topic):
        with self.lock:
            if not self.columns[topic].has_stamp:
                self.lock.wait_for(lambda: self.clocks >= self.triggered, CLOCK_WAIT_S)
            self.columns[topic].add(msg, self.clock)
            if topic in self.counts:
                self.counts[topic] += 1
                self.lock.notify_all()

    # --- start -----------------------------------------------------------------------------
    def subscribe(self, deadline):
        """Subscribes to every topic matching a pattern once each ``wait_for`` pattern (what
        the code must publish) has a publisher; the simulator's topics are there by then."""
        master = rosgraph.Master(rospy.get_name())
        rospy.wait_for_service(UNPAUSE_SERVICE, timeout=max(1.0, deadline - time.monotonic()))
        required = self.pace.get("wait_for", [])
        waits = required + self.pace.get("also_wait_for", [])
        previous = None
        while True:
            types = dict(master.getTopicTypes())
            missing = [p for p in required if not any(fnmatch.fnmatchcase(t, p) for t in types)]
            # the simulator registers its topics in batches: resolve the patterns once the
            # list has stopped growing (a metric may name alternatives: /imu or /accel)
            if not missing and previous == set(types):
                break
            previous = set(types)
            if time.monotonic() > deadline:
                raise RuntimeError(f"no topic matches {missing} (the simulator or the code "
                                   "never published them)")
            time.sleep(0.25)
        for topic in sorted(t for t in types if any(fnmatch.fnmatchcase(t, p)
                                                    for p in self.patterns)):
            cls = get_message_class(types[topic])
            self.columns[topic] = flatten.Columns(types[topic], cls)
            self.subs.append(rospy.Subscriber(topic, cls, self.on_message, topic,
                                              queue_size=10000, tcp_nodelay=True))
            if any(fnmatch.fnmatchcase(topic, p) for p in waits):
                self.counts[topic] = 0
                self.by_topic[topic] = self.subs[-1]
        while any(s.get_num_connections() == 0 for s in self.subs):
            if time.monotonic() > deadline:
                raise RuntimeError("could not connect to every recorded topic")
            time.sleep(0.02)
        if self.recorder:
            self._await_recorder(master, deadline)

    def _await_recorder(self, master, deadline):
        """A run with a bag: until ``rosbag record`` (which looks for the topics matching its
        pattern about once a second) has subscribed to every recorded topic, so that the bag
        holds the run from its first step; the start grace then gives it time to connect."""
        while True:
            subscribed = {t for t, names in master.getSystemState()[1] if self.recorder in names}
            missing = sorted(set(self.columns) - subscribed)
            if not missing:
                return
            if time.monotonic() > deadline:
                raise RuntimeError(f"{self.recorder} did not subscribe to {missing}")
            time.sleep(0.05)

    def restart(self, out):
        """As at the start, recording to ``out`` (a walk after the first: :mod:`probe_walks`)."""
        with self.lock:
            self.out = out
            self.clock, self.late_steps, self.triggered, self.clocks = 0.0, 0, 0, 0
            self.columns = {t: flatten.Columns(c.type_name, get_message_class(c.type_name))
                            for t, c in self.columns.items()}
            self.counts = {t: 0 for t in self.counts}

    def reconnect(self, deadline):
        """Until every recorded topic has a publisher connected again (the nodes restarted)."""
        while any(s.get_num_connections() == 0 for s in self.subs):
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise RuntimeError("could not connect to every recorded topic again")
            time.sleep(0.02)

    def await_ready(self, deadline):
        """Until each wait_for topic has had as many messages as when the launch's first walk
        started (the nodes' ready messages, sent again by a reset: :mod:`probe_walks`)."""
        with self.lock:
            while any(self.counts[t] < n for t, n in self.ready_counts.items()):
                if time.monotonic() > deadline or rospy.is_shutdown():
                    raise RuntimeError("the ready messages did not come again: " + ", ".join(
                        f"{t} {self.counts[t]} of {n}" for t, n in self.ready_counts.items()))
                self.lock.wait(GONE_POLL_S)

    def start(self, grace=True):
        """The run started, after ``start_grace_s`` for the user's nodes when ``grace``."""
        if grace:
            time.sleep(self.pace.get("start_grace_s", 0.5))
        with self.lock:
            if self.ready_counts is None:
                self.ready_counts = dict(self.counts)
        self.late_before = nodes_late_steps()       # the other nodes' count as the run starts
        if self.pace["mode"] == "lockstep":
            from vrep_common.srv import simRosSynchronous
            rospy.ServiceProxy(NODE_NAMESPACE + "simRosSynchronous", simRosSynchronous)(enable=1)
        rospy.ServiceProxy(UNPAUSE_SERVICE, Empty)()

    # --- the run ---------------------------------------------------------------------------
    def run_free(self):
        with self.lock:
            while self.clock < self.duration_s and not rospy.is_shutdown():
                self.lock.wait(0.1)

    def run_lockstep(self):
        from vrep_common.srv import simRosSynchronousTrigger
        trigger = rospy.ServiceProxy(NODE_NAMESPACE + "simRosSynchronousTrigger",
                                     simRosSynchronousTrigger, persistent=True)
        timeout = self.pace.get("step_timeout_s", 1.0)
        settle_s = self.pace.get("settle_s", 0.003)
        with self.lock:
            required = dict(self.counts)         # what came before the start answers no step
        while not rospy.is_shutdown():
            with self.lock:
                if self.clock >= self.duration_s:
                    return
                before_clock = self.clock
            time.sleep(settle_s)         # the answer reaches the simulator by its own connection
            with self.lock:
                self.triggered += 1
            trigger()
            required = {t: n + 1 for t, n in required.items()}
            deadline = time.monotonic() + timeout
            with self.lock:
                # answered: as many messages on each wait_for topic as steps so far (a node
                # whose timer fired twice in one step has answered the next one already); a
                # late step forgives what was missing, so one miss does not make all late
                while not rospy.is_shutdown():
                    answered = all(self.counts[t] >= n or self.gone(t)
                                   for t, n in required.items())
                    if self.clock > before_clock and answered:
                        break
                    left = deadline - time.monotonic()
                    if left <= 0:
                        self.late_steps += 1
                        required = {t: min(n, self.counts[t]) for t, n in required.items()}
                        break
                    self.lock.wait(min(left, GONE_POLL_S))

    def gone(self, topic):
        """With the pace's ``skip_gone``, a wait_for topic whose every publisher has gone (a
        node killed mid-run, as the safety benchmark's fault does) is not waited for: the run
        goes on at its pace. Off by default: a node that crashed keeps its steps late, which
        leaves roslaunch the time to report its death, so that the run is a failed row."""
        if not self.pace.get("skip_gone", False):
            return False
        sub = self.by_topic.get(topic)
        return sub is not None and sub.get_num_connections() == 0

    # --- the end ---------------------------------------------------------------------------
    def write(self, status, message=""):
        os.makedirs(os.path.dirname(self.out) or ".", exist_ok=True)
        with self.lock:
            recording = {t: c.series() for t, c in self.columns.items()}
            clock = self.clock
        metrics.save_recording(self.out + ".tmp.npz", recording)
        os.replace(self.out + ".tmp.npz", self.out)
        world = rospy.get_param(NODE_NAMESPACE + "world", "")
        self.times["done"] = time.time()
        info = {"status": status, "message": message, "sim_time_s": clock,
                "times": self.times,
                "late_steps": self.late_steps + nodes_late_steps() - self.late_before,
                "world": world,
                "messages": {t: int(s.t.size) for t, s in recording.items()}}
        with open(os.path.splitext(self.out)[0] + ".status.json", "w") as f:
            json.dump(info, f)


def main():
    rospy.init_node("experiment_probe")
    settings = {k: rospy.get_param("~" + k) for k in ("duration_s", "out", "topics", "pace",
                                                      "walks", "recorder")
                if rospy.has_param("~" + k)}
    if "duration_s" not in settings or "out" not in settings:
        rospy.logfatal("experiment_probe needs ~duration_s and ~out")
        return 2
    walks = probe_walks.walks_of(settings)
    probe = Probe({**settings, "out": walks[0]["out"]})
    rospy.Subscriber("/clock", Clock, probe.on_clock, queue_size=100)
    start_timeout_s = probe.pace.get("start_timeout_s", START_TIMEOUT_S)
    for number, walk in enumerate(walks):
        try:
            if number == 0:
                probe.subscribe(time.monotonic() + start_timeout_s)
                again = True
            else:
                again = probe_walks.next_walk(probe, walk, start_timeout_s)
            probe.times["ready"] = time.time()
            probe.start(grace=bool(again))
            probe.times["started"] = time.time()
        except (RuntimeError, OSError, rospy.ROSException, rospy.ServiceException) as e:
            rospy.logerr(f"experiment_probe: walk {number + 1} did not start: {e}")
            probe.out = walk["out"]
            probe.write("no_start", str(e))
            return 2 if number == 0 else 0
        (probe.run_lockstep if probe.pace["mode"] == "lockstep" else probe.run_free)()
        probe.write("done" if not rospy.is_shutdown() else "interrupted")
        rospy.loginfo(f"experiment_probe: walk {number + 1} of {len(walks)}: "
                      f"{probe.duration_s} s simulated, late steps {probe.late_steps}")
        if rospy.is_shutdown():
            break
    return 0


if __name__ == "__main__":
    sys.exit(main())

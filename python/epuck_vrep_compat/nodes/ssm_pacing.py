"""When the supervisor's cycle runs: on a timer in simulated time (the default), or, with
``~lockstep``, once per simulation step, on that step's inputs.

In lock-step the simulator waits for every supervised robot's speed scale after each step
(its ``~lockstep_timeout_s``), so the supervisor must answer every step, and answer it from
that step's inputs alone, whatever order they arrive in: a cycle runs when every supervised
robot's joint states of one stamp have arrived (and, for the robots' bases, TF at that stamp),
never twice for one stamp. Before the first step it sends each robot a latched scale 0 (not
supervising yet) once it hears their joint states' publisher: the simulator's signal that the
supervisor is ready.

With ``~lockstep_operator`` the cycle also waits for the operator's estimate of its step
(:class:`OperatorSteps`): the tracker in lock-step (:mod:`tracker_steps`) and a relay between
them send one message per step, in order, after a latched one stamped 0 when ready; the n-th
message after that one answers the n-th step, however late it comes (a fault that holds the
estimates back sends an old one, with its old stamp). Without it the cycle takes the latest
estimate, which may be the last step's or this one's.
"""
import threading
import time

import rospy
import tf2_ros

from epuck_vrep_compat.compat.frames import WORLD_FRAME
from epuck_vrep_compat.nodes.step_inputs import INPUT_TIMEOUT_S
from epuck_vrep_compat.ros.common.late_steps import LateSteps

LATE = LateSteps()      # inputs given up (a frame, an estimate): the experiment's late steps


class StepPacer:
    """Runs ``cycle(now)`` once per stamp on which every channel has joint states."""

    def __init__(self, channels, cycle, tf_listener, operator=None):
        """``tf_listener``: a :class:`step_inputs.NotifyingTransformListener`; ``operator``:
        the :class:`OperatorSteps` to wait for before the first step (None: none)."""
        self.channels = channels
        self.cycle = cycle
        self.tf_listener = tf_listener
        self.operator = operator
        self._lock = threading.Lock()
        self._last = rospy.Time(0)
        self._starts = 0             # restarts so far: a handshake of an earlier one sends nothing

    def handshake(self, start=0):
        """Once every channel's joint states have a publisher: a latched scale 0 each."""
        while not rospy.is_shutdown() and any(
                c.joints_subscriber.get_num_connections() == 0 for c in self.channels.values()):
            time.sleep(0.02)
        if self.operator is not None:
            self.operator.wait_ready()
        with self._lock:
            if start != self._starts:
                return
            for channel in self.channels.values():
                channel.command.publish(0.0)

    def restart(self):
        """As built (the supervisor reset): no step answered, the operator's estimates counted
        from the next ready message, and the handshake again, on a thread of its own (as at
        the start, it waits for the operator's ready message, which the tracker, reset after
        the supervisor, sends)."""
        with self._lock:
            self._last = rospy.Time(0)
            self._starts += 1
            start = self._starts
        if self.operator is not None:
            self.operator.restart()
        threading.Thread(target=self.handshake, args=(start,), daemon=True,
                         name="ssm_handshake").start()

    def on_joints(self, _stamp):
        """A robot's joint states arrived (its subscriber's thread)."""
        with self._lock:
            stamps = {c.joints.header.stamp if c.joints is not None else None
                      for c in self.channels.values()}
            if len(stamps) != 1 or None in stamps:
                return
            now = stamps.pop()
            if now <= self._last:
                return
            self._last = now
            self._await_tf(now)
            self.cycle(now=now)

    def _await_tf(self, now):
        """Each robot's root frame on TF at ``now`` (or the wait ends: the cycle then fails
        safe for lack of it, as a stale input does)."""
        for channel in self.channels.values():
            root = channel.root_frame()
            if root is not None and not self.tf_listener.wait_transform(WORLD_FRAME, root, now):
                rospy.logwarn("ssm_supervisor: no TF of %s at %.3f s within %.1f s", root,
                              now.to_sec(), INPUT_TIMEOUT_S)
                LATE.add()


class OperatorSteps:
    """The operator's estimates in lock-step: the n-th after the one stamped 0 is step n's."""

    def __init__(self):
        self._cond = threading.Condition()
        self._ready = False
        self._received = {}             # message number (1, 2, ...) -> message
        self._count = self._taken = 0

    def restart(self):
        """As built: not ready, nothing received or taken."""
        with self._cond:
            self._ready = False
            self._received, self._count, self._taken = {}, 0, 0
            self._cond.notify_all()

    def on_message(self, msg):
        """An estimate arrived (its subscriber's thread)."""
        with self._cond:
            if msg.header.stamp.is_zero():
                self._ready = True               # (again, when latched: changes nothing)
            elif self._ready:
                self._count += 1
                self._received[self._count] = msg
            self._cond.notify_all()

    def wait_ready(self):
        """Until the message stamped 0 has come."""
        with self._cond:
            while not self._ready and not rospy.is_shutdown():
                self._cond.wait(1.0)

    def next(self):
        """The next step's estimate, or None when it has not come within INPUT_TIMEOUT_S of
        wall time (the following step then still takes its own)."""
        deadline = time.monotonic() + INPUT_TIMEOUT_S
        with self._cond:
            self._taken += 1
            while self._count < self._taken and not rospy.is_shutdown():
                left = deadline - time.monotonic()
                if left <= 0.0:
                    rospy.logwarn("ssm_supervisor: no operator estimate of step %d within "
                                  "%.1f s", self._taken, INPUT_TIMEOUT_S)
                    LATE.add()
                    break
                self._cond.wait(left)
            for n in [n for n in self._received if n < self._taken]:
                del self._received[n]
            return self._received.pop(self._taken, None)


def lookup_root(tf_buffer, root, stamp):
    """The root's transform on TF at ``stamp`` (None: the latest), or None."""
    try:
        return tf_buffer.lookup_transform(WORLD_FRAME, root,
                                          stamp if stamp is not None else rospy.Time(0))
    except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
            tf2_ros.ExtrapolationException):
        return None

"""When the supervisor's cycle runs: on a timer in simulated time (the default), or, with
``~lockstep``, once per simulation step, on that step's inputs.

In lock-step the simulator waits for every supervised robot's speed scale after each step
(its ``~lockstep_timeout_s``), so the supervisor must answer every step, and answer it from
that step's inputs alone, whatever order they arrive in: a cycle runs when every supervised
robot's joint states of one stamp have arrived (and, for the robots' bases, TF at that stamp),
never twice for one stamp. Before the first step it sends each robot a latched scale 0 (not
supervising yet) once it hears their joint states' publisher: the simulator's signal that the
supervisor is ready.
"""
import threading
import time

import rospy
import tf2_ros

from epuck_vrep_compat.compat.frames import WORLD_FRAME

INPUT_TIMEOUT_S = 2.0           # wall time a lock-step cycle waits for TF at its stamp


class StepPacer:
    """Runs ``cycle(now)`` once per stamp on which every channel has joint states."""

    def __init__(self, channels, cycle, tf_buffer):
        self.channels = channels
        self.cycle = cycle
        self.tf_buffer = tf_buffer
        self._lock = threading.Lock()
        self._last = rospy.Time(0)

    def handshake(self):
        """Once every channel's joint states have a publisher: a latched scale 0 each."""
        while not rospy.is_shutdown() and any(
                c.joints_subscriber.get_num_connections() == 0 for c in self.channels.values()):
            time.sleep(0.02)
        for channel in self.channels.values():
            channel.command.publish(0.0)

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
        deadline = time.monotonic() + INPUT_TIMEOUT_S
        for channel in self.channels.values():
            root = channel.root_frame()
            while (root is not None and not rospy.is_shutdown()
                   and not self.tf_buffer.can_transform(WORLD_FRAME, root, now)):
                if time.monotonic() > deadline:
                    rospy.logwarn("ssm_supervisor: no TF of %s at %.3f s within %.1f s", root,
                                  now.to_sec(), INPUT_TIMEOUT_S)
                    break
                time.sleep(0.001)


def lookup_root(tf_buffer, root, stamp):
    """The root's transform on TF at ``stamp`` (None: the latest), or None."""
    try:
        return tf_buffer.lookup_transform(WORLD_FRAME, root,
                                          stamp if stamp is not None else rospy.Time(0))
    except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
            tf2_ros.ExtrapolationException):
        return None

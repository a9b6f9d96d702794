"""What a client node needs to compute each simulation step once, from that step's inputs, in
lock-step with the simulator (the nodes' ``~lockstep``; the simulator does not step on before
their answer, so a service of ``/vrep`` called meanwhile answers from that step's state).

- :func:`due`: whether a sensor of period T delivers at the step at t (the previous step at
  t_prev): it does when a multiple of T lies in (t_prev, t], the cell's laser's and the Kinect
  node's schedule alike, so a reader knows which steps bring a message without waiting for
  messages that never come.
- :class:`StepClock`: ``/clock``'s new times, each once, in order (a paused simulator's clock
  sent again is not a step).
- :class:`Inbox`: a stamped topic's newest message, taken once, and a wait for the one of a
  step (a condition: no polling).
- :class:`NotifyingTransformListener`: a tf2 listener whose every update wakes a wait for a
  frame (:meth:`~NotifyingTransformListener.wait_transform`) instead of polling the buffer.
"""
import math
import threading
import time

import rospy
import tf2_ros
from rosgraph_msgs.msg import Clock

INPUT_TIMEOUT_S = 2.0     # wall time a step waits for an input before going on without it
GONE_CHECK_S = 0.05       # how often such a wait asks whether the input's publisher has gone
_EPS = 1e-6


def due(t_prev: float, t: float, period_s: float) -> bool:
    """True when a sensor of period ``period_s`` (<= 0: none) delivers at the step at ``t``."""
    if period_s <= 0.0:
        return False
    return math.floor(t / period_s + _EPS) > math.floor(t_prev / period_s + _EPS)


class StepClock:
    """Calls ``on_step(stamp, previous stamp)`` once per new simulated time on ``/clock`` (on
    its subscriber's thread, so steps are handled one after the other, in order)."""

    def __init__(self, on_step):
        self._on_step = on_step
        self.last = rospy.Time(0)
        self.subscriber = rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=100)

    def reset(self):
        """As built: the next ``/clock`` time above 0 is a step (a rewound simulator)."""
        self.last = rospy.Time(0)

    def _on_clock(self, msg):
        if msg.clock <= self.last:
            return
        previous, self.last = self.last, msg.clock
        self._on_step(msg.clock, previous)


class Inbox:
    """The newest message of a stamped topic (``put`` from its subscriber); ``frame_id``: the
    last message's frame (a sensor's name), empty before the first."""

    def __init__(self):
        self._cond = threading.Condition()
        self._msg = None
        self.frame_id = ""

    def put(self, msg):
        with self._cond:
            self._msg = msg
            self.frame_id = msg.header.frame_id
            self._cond.notify_all()

    def reset(self):
        """As built: nothing waiting, no frame."""
        with self._cond:
            self._msg, self.frame_id = None, ""

    def take(self):
        """The newest message not taken yet, or None."""
        with self._cond:
            msg, self._msg = self._msg, None
            return msg

    def discard_before(self, stamp):
        """Forgets a waiting message stamped before ``stamp``: in lock-step a step uses only
        its own inputs (a message sent before the start, which a subscriber may or may not
        have heard, would make one run differ from the next)."""
        with self._cond:
            if self._msg is not None and self._msg.header.stamp < stamp:
                self._msg = None

    def wait_for(self, stamp, timeout_s=INPUT_TIMEOUT_S, gone=lambda: False) -> bool:
        """Until a message stamped ``stamp`` or later is waiting (True), ``timeout_s`` of wall
        time passed or ``gone()`` says its publisher has gone (False)."""
        deadline = time.monotonic() + timeout_s
        with self._cond:
            while self._msg is None or self._msg.header.stamp < stamp:
                left = deadline - time.monotonic()
                if left <= 0.0 or gone() or rospy.is_shutdown():
                    return False
                self._cond.wait(min(left, GONE_CHECK_S))
            return True


class NotifyingTransformListener(tf2_ros.TransformListener):
    """tf2's listener, filling ``buffer``, that wakes :meth:`wait_transform` on every update."""

    def __init__(self, buffer):
        self.changed = threading.Condition()
        super().__init__(buffer)

    def callback(self, data):
        super().callback(data)
        with self.changed:
            self.changed.notify_all()

    def static_callback(self, data):
        super().static_callback(data)
        with self.changed:
            self.changed.notify_all()

    def wait_transform(self, target, source, stamp, timeout_s=INPUT_TIMEOUT_S) -> bool:
        """Until ``source`` in ``target`` at ``stamp`` is known (True) or ``timeout_s`` of wall
        time passed (False)."""
        deadline = time.monotonic() + timeout_s
        with self.changed:
            while not self.buffer.can_transform(target, source, stamp):
                left = deadline - time.monotonic()
                if left <= 0.0 or rospy.is_shutdown():
                    return False
                self.changed.wait(left)
            return True

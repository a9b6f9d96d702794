"""A client node's ``~reset`` (``std_srvs/Trigger``): the node as it was launched, without a new
process, for the next run of one launch (the experiment runner's ``runs_per_launch``: the probe
calls it after ``/vrep/rewind``, docs/experiments.md, Several runs per launch).

A node that offers it promises that after a successful answer it holds nothing of the run
before: what it received, counted, filtered, latched or waited for is as at its start, and it
has sent again what it sends at its start (a latched ready message), or sends it as it would
at its start (once what it waits for has come). A node that cannot (a fault it injected that
no reset undoes) answers ``success`` false with why: the probe then runs the next walk alone.

The pieces every such node needs: :class:`ResetService` (the service, one reset at a time),
:func:`restart_ros_time` (rospy's simulated time back to 0, as before a node's first
``/clock``: tf2's listener and rospy's timers compare against it), :func:`clear_tf` (a tf2
listener's buffer without the run's transforms; the static ones, latched once, are kept) and
:func:`forget_latched` (a latched publisher with nothing to hand a new subscriber).
"""
import threading

import rospy
from std_srvs.srv import Trigger, TriggerResponse

from epuck_vrep_compat.compat.topics import NODE_RESET_SERVICE


class ResetRefused(Exception):
    """The node cannot be as launched (the message says why)."""


class ResetService:
    """``~reset``: calls ``reset()`` (which may raise :class:`ResetRefused`) one at a time."""

    def __init__(self, reset):
        self._reset = reset
        self._lock = threading.Lock()
        self.count = 0                      # resets done
        self.service = rospy.Service("~" + NODE_RESET_SERVICE, Trigger, self._on_reset)

    def _on_reset(self, _req):
        with self._lock:
            try:
                self._reset()
            except ResetRefused as why:
                rospy.logwarn("%s: reset refused: %s", rospy.get_name(), why)
                return TriggerResponse(success=False, message=str(why))
            self.count += 1
        rospy.loginfo("%s: reset (%d): as launched", rospy.get_name(), self.count)
        return TriggerResponse(success=True, message="")


def restart_ros_time():
    """rospy's time back to 0 under ``/use_sim_time`` (as a node's before the first ``/clock``;
    the simulator, rewound, sends none before its first step); wall time is left alone."""
    if rospy.get_param("/use_sim_time", False):
        rospy.rostime._set_rostime(rospy.Time(0))     # noqa: SLF001  rospy's own setter


def clear_tf(listener):
    """The run's transforms gone from ``listener``'s buffer (the static ones kept: a new
    listener would have them, latched, at once), and its check for time jumping back from 0."""
    with listener.last_update_lock:
        listener.buffer.clear()
        listener.last_update = rospy.Time(0)


def forget_latched(publisher):
    """A latched publisher that hands a new subscriber nothing until it publishes again."""
    publisher.impl.latch = None

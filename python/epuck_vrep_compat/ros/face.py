"""The one shape of every ROS face of the simulator node.

A face turns the simulation's state into ROS messages and ROS commands into the simulation's
inputs. Faces only read the simulation's state after a step; commands from subscribers go into
the model through its command methods. The simulator node (``ros/node/simulator_node.py``)
holds its faces in one list, in publication order, and calls, under the simulation lock:

* :meth:`Face.sync` after robots or objects came or went (between steps): advertise the new
  ones' topics, unadvertise the removed ones', lay out the messages again;
* :meth:`Face.publish` after every step, with a :class:`Step`: queue this step's messages in
  ``step.batch`` (or publish them directly, for the few non-batched topics);
* :meth:`Face.publish_idle` on the loop's idle passes (paused, stopped, waiting for a
  synchronous trigger); most faces publish nothing then.

No face's output is another's input: each reads the model alone (what must be published
from the start, such as the cell's blob signals, the model declares), so the list's order
does not change what a topic gets in a step (``/tf``, which several faces share, gets their
messages in the list's order: independent transforms, in any order).
"""
import rospy


class Step:
    """What every face gets to publish one step: the simulation time stamp (``secs``,
    ``nsecs``), the node's :class:`~epuck_vrep_compat.ros.transport.step_batch.StepBatch` and
    the shared ``/tf`` publisher, whose per-step messages go through that batch."""

    __slots__ = ("secs", "nsecs", "batch", "tf")

    def __init__(self, secs: int, nsecs: int, batch, tf):
        self.secs = secs
        self.nsecs = nsecs
        self.batch = batch
        self.tf = tf

    @property
    def stamp(self) -> rospy.Time:
        return rospy.Time(self.secs, self.nsecs)


class Face:
    """Base of the simulator node's faces (see the module's docstring for the protocol)."""

    def sync(self):
        """Robots or objects came or went: follow them (default: nothing to follow)."""

    def publish(self, step: Step):
        """After a simulation step: this step's messages."""
        raise NotImplementedError

    def publish_idle(self, step: Step):
        """While the simulation does not step (default: nothing)."""

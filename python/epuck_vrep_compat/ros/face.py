"""The one shape of every ROS face of the simulator node.

A face turns the simulation's state into ROS messages and ROS commands into the simulation's
inputs. Faces only read the simulation's state after a step; commands from subscribers go into
the model through its command methods. The simulator node (``ros/node/simulator_node.py``)
holds its faces in one list and calls on each, under the simulation lock:

* :meth:`Face.sync` after robots or objects came or went (between steps): advertise the new
  ones' topics, unadvertise the removed ones', lay out the messages again;
* :meth:`Face.publish` after every step, with a :class:`Step`: queue this step's messages in
  ``step.batch`` (or publish them directly, for the few non-batched topics);
* :meth:`Face.publish_idle` on the loop's idle passes (paused, stopped, waiting for a
  synchronous trigger); most faces publish nothing then.

No face's output is another's input: each reads the model alone (what must be published
from the start, such as the cell's blob signals, the model declares), and where faces share a
topic the node orders their messages (``/clock`` first; on ``/tf`` the parts of
``TF_PARTS``), so the list's order does not change what any topic gets.
"""
import rospy

# The order of a step's messages on /tf, whatever the order of the faces (a rule of the node,
# as /clock first): tf2 keeps the first of two transforms of one frame and stamp.
TF_PARTS = ("epucks", "cell", "streams")


class Step:
    """What every face gets to publish one step: the simulation time stamp (``secs``,
    ``nsecs``), the node's :class:`~epuck_vrep_compat.ros.transport.step_batch.StepBatch` and
    the shared ``/tf`` publisher, whose per-step messages faces hand to :meth:`add_tf`."""

    __slots__ = ("secs", "nsecs", "batch", "tf", "_tf_parts")

    def __init__(self, secs: int, nsecs: int, batch, tf):
        self.secs = secs
        self.nsecs = nsecs
        self.batch = batch
        self.tf = tf
        self._tf_parts = {}

    def add_tf(self, part: str, msg):
        """One part's ``/tf`` message of this step (a part of ``TF_PARTS``; a genpy message, or
        a framed pre-serialised one as ``bytes``), queued by :meth:`send_tf`."""
        self._tf_parts[part] = msg

    def send_tf(self):
        """The step's ``/tf`` messages into the batch, in ``TF_PARTS`` order (the node, after
        every face published)."""
        for part in TF_PARTS:
            msg = self._tf_parts.pop(part, None)
            if isinstance(msg, bytes):
                self.batch.add_frame(self.tf, msg)
            elif msg is not None:
                self.batch.add(self.tf, msg)

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

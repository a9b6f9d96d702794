"""``/tf_static``: the node's frames that never move relative to their parent, sent once.

As ``robot_state_publisher`` and tf2's static broadcaster do, the static transforms go on one
latched topic, so a listener that joins at any time gets them at once, and the per-step ``/tf``
carries only frames that move. A latched topic keeps only its last message, so every part of
the node (the e-pucks, the cell) hands its static transforms to one :class:`StaticTransforms`,
which publishes them all together whenever a part changes (robots came or went, a device was
moved). rospy's Python ``StaticTransformBroadcaster`` would instead replace one part's frames
with the next part's.
"""
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage

from epuck_vrep_compat.compat.topics import TF_STATIC_TOPIC
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher


def static_transform(parent, child, translation, quat, secs=0, nsecs=0) -> TransformStamped:
    """One transform ``parent -> child`` (translation in m, quaternion x, y, z, w)."""
    t = TransformStamped()
    t.header.stamp.secs, t.header.stamp.nsecs = secs, nsecs
    t.header.frame_id = parent
    t.child_frame_id = child
    v, q = t.transform.translation, t.transform.rotation
    v.x, v.y, v.z = (float(x) for x in translation)
    q.x, q.y, q.z, q.w = (float(x) for x in quat)
    return t


class StaticTransforms:
    """The node's one latched ``/tf_static`` publisher and the static transforms of each part.

    ``publisher``: replaces the latched rospy publisher (tests)."""

    def __init__(self, publisher=None):
        self._pub = publisher or synchronous_publisher(TF_STATIC_TOPIC, TFMessage, latch=True)
        self._parts = {}

    def set(self, part: str, transforms):
        """Replace ``part``'s static transforms and publish every part's (when they changed)."""
        transforms = list(transforms)
        if self._parts.get(part) == transforms:
            return
        self._parts[part] = transforms
        self._pub.publish(TFMessage(transforms=[t for ts in self._parts.values() for t in ts]))

    def transforms(self, part: str):
        """The static transforms ``part`` set last (empty if none)."""
        return list(self._parts.get(part, ()))

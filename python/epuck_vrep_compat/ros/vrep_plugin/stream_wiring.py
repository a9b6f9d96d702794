"""The rospy side of the ``/vrep`` streams: advertising, subscribing, what the node already has."""
from typing import Optional

import rosgraph.names
import rospy
from rospy.impl.registration import get_topic_manager

from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher


class RospyWiring:
    """The rospy side of the streams, apart so the unit tests can replace it."""

    def advertise(self, resolved: str, msg_class):
        return synchronous_publisher(resolved, msg_class)      # data goes through StepBatch

    def subscribe(self, resolved: str, msg_class, callback, callback_args, queue_size):
        return rospy.Subscriber(resolved, msg_class, callback, callback_args,
                                queue_size=queue_size)

    def publication_exists(self, resolved: str) -> bool:
        """Our node already publishes that topic (rospy would share it, whatever the type)."""
        return get_topic_manager().has_publication(resolved)

    def subscription_type(self, resolved: str) -> Optional[str]:
        impl = get_topic_manager().get_subscriber_impl(resolved)
        return None if impl is None else impl.data_class._type

    @staticmethod
    def is_legal(resolved: str) -> bool:
        return rosgraph.names.is_legal_name(resolved)

"""Latched topics through the step batch: the last message kept per topic, sent to each new
subscriber by the batch's writer, before anything newer.

rospy's latch writes the last message to a new connection itself, from its accept thread, with
a blocking ``sendall`` on the descriptor the batch's writer uses for that connection: the two
would race (bytes interleaved, or the old state arriving after a newer one). A latched topic
made by :meth:`LatchedTopics.publisher` lets rospy latch nothing (its connection header still
says ``latching=1``, which subscribers and recorders read); a subscriber listener notes the
topics that gained a connection, from rospy's accept thread, and the batch's next flush takes
them (:meth:`LatchedTopics.joined`) and queues each one's last frame for every connection that
has had nothing from the writer yet. A late subscriber thus gets the last state at the next
flush: every step, or every idle pass while the simulation does not step. Each robot's
``led_state`` is one: with rospy's queued latched publishers a subscriber to everything at
1000 robots cost the node 1000 idle writer threads.
"""
import collections

import rospy


class LatchedTopics:
    """The last frame of every latched topic of one batch, and the topics that gained a
    connection since the batch last looked."""

    def __init__(self):
        self._frames = {}                     # publisher impl -> its last frame sent
        self._next = {}                       # impl -> its last frame queued, not yet sent
        self._joined = collections.deque()    # impls with a new connection (any thread)

    def publisher(self, topic, msg_class, make_publisher):
        """A latched topic whose new connections are noted here; ``make_publisher``: the
        batch's ``synchronous_publisher``."""
        listener = _JoinListener(self._joined)
        pub = make_publisher(topic, msg_class, latch=True, subscriber_listener=listener)
        listener.impl = pub.impl
        return pub

    def keep(self, impl, frame: bytes):
        """The topic's newest frame, queued for its subscribers now and kept for later ones
        from the end of this flush (:meth:`sent`): a connection that joins before that gets
        the frame sent before it, then this one, never this one twice."""
        self._next[impl] = frame

    def sent(self):
        """The batch flushed: the frames queued meanwhile are now the topics' last."""
        self._frames.update(self._next)
        self._next.clear()

    def joined(self):
        """(impl, last frame) of each open topic that gained a connection since the last call
        and has a last frame."""
        while self._joined:
            impl = self._joined.popleft()
            frame = self._frames.get(impl)
            if frame is not None and not impl.closed:
                yield impl, frame

    def forget_closed(self):
        """Drop the frames of topics closed since (a robot removed)."""
        for impl in [impl for impl in self._frames if impl.closed]:
            del self._frames[impl]
            self._next.pop(impl, None)


class _JoinListener(rospy.SubscribeListener):
    """Notes a latched topic that gained a connection (called on rospy's accept thread)."""

    def __init__(self, joined):
        self._joined = joined
        self.impl = None

    def peer_subscribe(self, topic_name, topic_publish, peer_publish):
        if self.impl is not None:
            self._joined.append(self.impl)

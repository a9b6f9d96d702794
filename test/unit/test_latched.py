"""Latched topics through the step batch (no master): a subscriber that joins late gets the
last state at the next flush, before anything newer and never twice; rospy latches nothing
itself (it would write from its accept thread, racing the batch's writer)."""
import socket
import struct

import pytest
import rospy.core
from std_msgs.msg import UInt8MultiArray

from epuck_vrep_compat.ros.transport.step_batch import StepBatch
from test_idle_faces import Subscriber


@pytest.fixture
def batch(monkeypatch):
    # rospy refuses publishers before init_node; with no master the publishers work locally
    monkeypatch.setattr(rospy.core, "_client_ready", True)
    yield StepBatch()
    while Subscriber.opened:
        Subscriber.opened.pop().close()


def states(subscriber):
    """The states the subscriber's socket received since the last call."""
    try:
        data = subscriber._peer.recv(1 << 16, socket.MSG_DONTWAIT)
    except BlockingIOError:
        return []
    out = []
    while data:
        (size,) = struct.unpack_from("<I", data)
        out.append(bytes(UInt8MultiArray().deserialize(data[4:4 + size]).data))
        data = data[4 + size:]
    return out


def state(value):
    return UInt8MultiArray(data=bytes([value]))


def test_a_late_subscriber_gets_the_last_state_then_what_is_newer_and_nothing_twice(batch):
    pub = batch.latched_publisher("/test_latched/state", UInt8MultiArray)
    batch.add_latched(pub, state(1))
    batch.flush()
    batch.add_latched(pub, state(2))          # nobody subscribed: only kept
    batch.flush()
    early = Subscriber("/early")
    pub.impl.add_connection(early)
    assert early.written == []                # rospy wrote nothing itself
    batch.flush()
    assert states(early) == [b"\x02"]
    batch.flush()
    assert states(early) == []                # once
    batch.add_latched(pub, state(3))
    late = Subscriber("/late")                # joins while a newer state waits to be sent
    pub.impl.add_connection(late)
    batch.flush()
    assert states(early) == [b"\x03"]
    assert states(late) == [b"\x02", b"\x03"]
    assert late.written == []


def test_the_topic_says_it_is_latched(batch):
    pub = batch.latched_publisher("/test_latched/header", UInt8MultiArray)
    assert pub.impl.is_latch and pub.impl.latch is None

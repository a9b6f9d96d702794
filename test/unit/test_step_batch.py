"""StepBatch's data path against a real socket whose reader stops: flushing never blocks, the
backlog stays bounded, whole messages arrive in order once the reader comes back, and a closed
reader's connection is dropped."""
import socket
import struct
import time
import types

import pytest

from epuck_vrep_compat.ros.transport import step_batch
from epuck_vrep_compat.ros.transport.step_batch import StepBatch

FRAME = struct.Struct("<I")


class FakeConnection:
    """The parts of rospy's TCPROSTransport that StepBatch touches, on a real socket."""

    def __init__(self, sock):
        self.socket = sock
        self.done = False
        self.endpoint_id = "/slow_reader"
        self.stat_bytes = 0

    def close(self):
        self.done = True


class FakeImpl:
    def __init__(self, connection):
        self.connections = [connection]
        self.closed = False
        self.resolved_name = "/topic"

    def remove_connection(self, connection):
        self.connections = [c for c in self.connections if c is not connection]


class FakePublisher:
    def __init__(self, impl):
        self.impl = impl


def small_pair():
    """A connected socket pair with small buffers, so that a reader that stops fills them soon."""
    writer, reader = socket.socketpair()
    writer.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 16384)
    reader.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 16384)
    return writer, reader


@pytest.fixture
def pair():
    writer, reader = small_pair()
    yield writer, reader
    writer.close()
    reader.close()


def message(seq, size=10000):
    body = struct.pack("<I", seq) + bytes(size - 4)
    return FRAME.pack(len(body)) + body


def read_all(sock):
    sock.setblocking(False)
    data = b""
    while True:
        try:
            chunk = sock.recv(1 << 20)
        except BlockingIOError:
            return data
        if not chunk:
            return data
        data += chunk


def frames(data):
    out, i = [], 0
    while i < len(data):
        (n,) = FRAME.unpack_from(data, i)
        assert i + 4 + n <= len(data), "a partial message reached the reader"
        out.append(struct.unpack_from("<I", data, i + 4)[0])
        i += 4 + n
    return out


@pytest.mark.parametrize("background", [False, True])
def test_a_reader_that_stops_never_blocks_the_writer_and_loses_only_whole_batches(pair,
                                                                                  background):
    writer, reader = pair
    connection = FakeConnection(writer)
    pub = FakePublisher(FakeImpl(connection))
    cap = 100000
    batch = StepBatch(max_backlog_bytes=cap, background=background)
    for seq in range(500):                       # 5 MB, the reader takes nothing
        batch.add_frame(pub, message(seq))
        batch.flush()                            # would block forever with sendall
        batch.settle()
        assert batch.backlog_bytes <= cap + 10004
    assert batch.backlog_bytes > 0
    # a TCP stream has no message boundaries: the reader keeps what it got and parses the
    # whole stream; a dropped partial message would break the parse
    stream = read_all(reader)
    for _ in range(100):                         # the reader is back: the backlog drains
        batch.flush()
        batch.settle()
        stream += read_all(reader)
        if batch.backlog_bytes == 0:
            break
    assert batch.backlog_bytes == 0
    received = frames(stream)
    assert received == sorted(received) and len(set(received)) == len(received)
    assert received[0] == 0 and received[-1] == 499
    assert 10 < len(received) < 500             # some dropped, the rest whole and in order
    assert connection in pub.impl.connections


@pytest.mark.parametrize("background", [False, True])
def test_a_lagging_reader_of_small_messages_holds_at_most_the_batch_limit(pair, background):
    """Messages far under the byte cap: the backlog holds at most ``max_backlog_batches``
    batches (one per flush), so many such subscriptions cannot add up to gigabytes."""
    writer, reader = pair
    pub = FakePublisher(FakeImpl(FakeConnection(writer)))
    batch = StepBatch(max_backlog_batches=5, background=background)
    for seq in range(3000):                      # about 300 kB: fills the socket, then more
        batch.add_frame(pub, message(seq, 100))
        batch.flush()
        batch.settle()
        assert batch.backlog_bytes <= 5 * 104          # framed: 4 + 100 bytes
    assert batch.backlog_bytes > 0
    stream = read_all(reader)
    for _ in range(100):
        batch.flush()
        batch.settle()
        stream += read_all(reader)
        if batch.backlog_bytes == 0:
            break
    received = frames(stream)
    assert received == sorted(received) and received[-1] == 2999 and len(received) < 3000


@pytest.mark.parametrize("background", [False, True])
def test_a_fast_reader_gets_everything(pair, background):
    writer, reader = pair
    pub = FakePublisher(FakeImpl(FakeConnection(writer)))
    batch = StepBatch(background=background)
    received = []
    for seq in range(200):
        batch.add_frame(pub, message(seq, 100))
        batch.add_frame(pub, message(1000 + seq, 100))
        batch.flush()
        batch.settle()
        received += frames(read_all(reader))     # small messages: each flush arrives whole
    assert received == [v for seq in range(200) for v in (seq, 1000 + seq)]


@pytest.mark.parametrize("background", [False, True])
def test_a_closed_reader_is_dropped(pair, background):
    writer, reader = pair
    pub = FakePublisher(FakeImpl(FakeConnection(writer)))
    batch = StepBatch(background=background)
    reader.close()
    for seq in range(3):
        batch.add_frame(pub, message(seq))
        batch.flush()
    batch.settle()
    assert pub.impl.connections == []


def test_a_failure_reported_after_its_topic_was_closed_is_let_go(pair):
    # rospy's close() sets the topic's connection list to None (a robot removed, shutdown); a
    # failure the writer reports for one of its connections afterwards must not end the step
    # loop (it did, in vrep_models: TypeError in rospy's remove_connection)
    writer, _reader = pair
    connection = FakeConnection(writer)
    pub = FakePublisher(FakeImpl(connection))
    batch = StepBatch(background=False)
    batch.add_frame(pub, message(0))
    batch.flush()
    writer_id = batch._ids[connection][0]
    pub.impl.closed, pub.impl.connections = True, None
    batch._apply([(writer_id, 0, True)])              # the writer's report: failed
    assert batch._ids == {} and connection.done


def test_rospys_close_takes_the_connection_out_of_the_writer_first(pair):
    writer, reader = pair
    connection = FakeConnection(writer)
    pub = FakePublisher(FakeImpl(connection))
    batch = StepBatch(background=True)
    batch.add_frame(pub, message(1, 100))
    batch.flush()
    batch.settle()
    assert frames(read_all(reader)) == [1]
    assert connection.stat_bytes == 104
    connection.close()                           # as rospy drops a dead connection
    assert connection.done and batch._writer.connection_count == 0
    batch.add_frame(pub, message(2, 100))        # rospy has not taken it off the list yet
    batch.flush()
    batch.settle()
    assert read_all(reader) == b""


@pytest.mark.parametrize("background", [False, True])
def test_a_connection_closed_before_its_first_flush_is_dropped_and_the_batch_goes_on(background):
    # rospy closed the socket (fileno() -1) before the batch ever took the connection over,
    # as a subscriber that connects and leaves at once; the simulator must not fail
    gone_writer, gone_reader = socket.socketpair()
    gone_writer.close()
    gone_reader.close()
    writer, reader = socket.socketpair()
    gone, alive = FakeConnection(gone_writer), FakeConnection(writer)
    impl = FakeImpl(gone)
    impl.connections.append(alive)
    pub = FakePublisher(impl)
    batch = StepBatch(background=background)
    batch.add_frame(pub, message(7, 100))
    batch.flush()
    batch.settle()
    assert impl.connections == [alive]
    assert frames(read_all(reader)) == [7]
    assert batch._writer.connection_count == 1
    writer.close()
    reader.close()


def test_a_subscriber_lagging_on_many_topics_gets_one_warning_naming_them(monkeypatch):
    """A subscriber that stops reading every topic (rosbag record -a at 1000 robots) is warned
    about once per period, not once per topic; the line counts and names its topics."""
    lines = []
    monkeypatch.setattr("rospy.logwarn", lambda fmt, *args: lines.append(fmt % args))
    pairs = [small_pair() for _ in range(6)]
    try:
        pubs = []
        for k, (writer, _reader) in enumerate(pairs):
            impl = FakeImpl(FakeConnection(writer))
            impl.resolved_name = f"/ePuck{k}/proximity0"
            pubs.append(FakePublisher(impl))
        batch = StepBatch(max_backlog_batches=2)
        for seq in range(40):                    # 400 kB each: every socket fills, then drops
            for pub in pubs:
                batch.add_frame(pub, message(seq))
            batch.flush()
        assert len(lines) == 1, lines            # at the first drop, then not again in 10 s
        assert lines[0].startswith("subscriber /slow_reader is not reading: 1 batches ")
        later = types.SimpleNamespace(monotonic=lambda: time.monotonic() + 11.0)
        monkeypatch.setattr(step_batch, "time", later)      # the period has passed
        for pub in pubs:
            batch.add_frame(pub, message(40))
        batch.flush()
        assert len(lines) == 2, lines            # the next names what lagged meanwhile
        assert "on 6 topic(s) (/ePuck0/proximity0, /ePuck1/proximity0, /ePuck2/proximity0, ...)" \
            in lines[1]
    finally:
        for writer, reader in pairs:
            writer.close()
            reader.close()

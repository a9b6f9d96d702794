"""StepBatch's data path against a real socket whose reader stops: flushing never blocks, the
backlog stays bounded, whole messages arrive in order once the reader comes back, and a closed
reader's connection is dropped."""
import socket
import struct

import pytest

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


@pytest.fixture
def pair():
    writer, reader = socket.socketpair()
    writer.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 16384)
    reader.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 16384)
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

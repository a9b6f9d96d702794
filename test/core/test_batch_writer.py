"""BatchWriter (the faces' send path in C++) on real socket pairs: byte-identical streams in
order, never blocking, bounded backlogs that drop only whole batches, failures reported, its own
duplicate of each descriptor."""
import errno
import os
import resource
import socket
import struct

import numpy as np
import pytest

from epuck_vrep_compat import _core

FRAME = struct.Struct("<I")


@pytest.fixture
def pair():
    writer, reader = socket.socketpair()
    writer.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 16384)
    reader.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 16384)
    yield writer, reader
    writer.close()
    reader.close()


def batch(seq, size):
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


def sequence_numbers(stream):
    out, i = [], 0
    while i < len(stream):
        (n,) = FRAME.unpack_from(stream, i)
        assert i + 4 + n <= len(stream), "a partial message in the stream"
        out.append(struct.unpack_from("<I", stream, i + 4)[0])
        i += 4 + n
    return out


def test_a_reader_that_keeps_up_gets_the_same_bytes_in_order(pair):
    sender, reader = pair
    writer = _core.BatchWriter(1 << 20)
    wid = writer.open(sender.fileno())
    sent, received = b"", b""
    for seq in range(300):
        data = batch(seq, 50 + seq % 200)
        writer.queue(wid, data)
        sent += data
        assert writer.flush() == []              # nothing went wrong
        assert writer.take_sent_bytes() == [(wid, len(data))]
        received += read_all(reader)
    assert received == sent
    assert writer.backlog_bytes == 0 and writer.take_sent_bytes() == []


def test_sent_bytes_without_waiting_are_counted_once(pair):
    """take_sent_bytes(wait=False), which the step loop calls so as never to wait for the
    writer's thread, returns what was sent when no flush holds the writer, and only once."""
    sender, reader = pair
    writer = _core.BatchWriter(1 << 20)
    wid = writer.open(sender.fileno())
    total = 0
    for seq in range(20):
        data = batch(seq, 100 + seq)
        writer.queue(wid, data)
        total += len(data)
        assert writer.flush() == []
        read_all(reader)
    assert writer.take_sent_bytes(False) == [(wid, total)]
    assert writer.take_sent_bytes(False) == [] and writer.take_sent_bytes(True) == []


def test_a_stalled_reader_never_blocks_and_loses_only_whole_batches(pair):
    sender, reader = pair
    cap, size = 100000, 10004
    writer = _core.BatchWriter(cap)
    wid = writer.open(sender.fileno())
    dropped = 0
    for seq in range(500):                       # 5 MB, the reader takes nothing
        writer.queue(wid, batch(seq, size - 4))
        for report_id, lost, failed in writer.flush():
            assert report_id == wid and not failed
            dropped += lost
        assert writer.backlog_bytes <= cap + size
    stream = read_all(reader)
    for _ in range(100):                         # the reader is back: the backlog drains
        writer.flush()
        stream += read_all(reader)
        if writer.backlog_bytes == 0:
            break
    assert writer.backlog_bytes == 0
    received = sequence_numbers(stream)
    assert received == sorted(received) and received[0] == 0 and received[-1] == 499
    assert len(received) + dropped == 500 and dropped > 0


def test_a_backlog_keeps_at_most_max_backlog_batches_however_small(pair):
    """Small batches far under the byte cap: the batch limit alone bounds the backlog (head
    plus the newest), and what the reader then gets is whole and in order."""
    sender, reader = pair
    limit, size = 8, 200
    writer = _core.BatchWriter(1 << 30, limit)
    assert writer.max_backlog_batches == limit
    wid = writer.open(sender.fileno())
    dropped, queued = 0, 0
    while True:                                  # fill the socket, then stall it for long
        writer.queue(wid, batch(queued, size))
        queued += 1
        for _id, lost, failed in writer.flush():
            assert not failed
            dropped += lost
        if writer.backlog_bytes > 0:
            break
    for _ in range(200):
        writer.queue(wid, batch(queued, size))
        queued += 1
        for _id, lost, failed in writer.flush():
            assert not failed
            dropped += lost
        assert writer.backlog_bytes <= limit * (size + 4)   # framed: 4 + size bytes
    assert dropped >= 200 - limit
    stream = read_all(reader)
    for _ in range(100):
        writer.flush()
        stream += read_all(reader)
        if writer.backlog_bytes == 0:
            break
    received = sequence_numbers(stream)
    assert received == sorted(received) and received[-1] == queued - 1
    assert len(received) + dropped == queued
    # the newest limit - 1 batches all survive, behind the head
    assert received[-(limit - 1):] == list(range(queued - limit + 1, queued))


def test_a_batch_limit_of_zero_is_refused():
    with pytest.raises(ValueError, match="at least 1"):
        _core.BatchWriter(1 << 20, 0)


def test_a_closed_reader_is_reported_failed_and_closing_forgets_it(pair):
    sender, reader = pair
    writer = _core.BatchWriter(1 << 20)
    wid = writer.open(sender.fileno())
    reader.close()
    writer.queue(wid, batch(0, 100))
    assert writer.flush() == [(wid, 0, True)]
    assert writer.take_sent_bytes() == []
    writer.close(wid)
    assert writer.connection_count == 0
    writer.queue(wid, b"x")                      # a closed connection's batches go nowhere
    assert writer.flush() == [] and writer.backlog_bytes == 0


def test_the_writers_thread_sends_while_the_caller_queues(pair):
    sender, reader = pair
    writer = _core.BatchWriter(1 << 20)
    wid = writer.open(sender.fileno())
    sent, received, reports = b"", b"", []
    for seq in range(300):
        data = batch(seq, 60 + seq % 100)
        writer.queue(wid, data)
        sent += data
        writer.request_flush()                   # returns at once; the thread sends
        reports += writer.take_reports(False)
        received += read_all(reader)
    reports += writer.take_reports(True)         # every requested flush done
    received += read_all(reader)
    for _ in range(100):                         # what a full socket left in the backlog
        if writer.backlog_bytes == 0:
            break
        writer.request_flush()
        reports += writer.take_reports(True)
        received += read_all(reader)
    assert received == sent
    assert reports == []                         # nothing dropped, nothing failed
    assert writer.take_sent_bytes() == [(wid, len(sent))]


def test_the_writer_keeps_its_own_descriptor(pair):
    sender, reader = pair
    writer = _core.BatchWriter(1 << 20)
    wid = writer.open(sender.fileno())
    assert wid != sender.fileno()
    sender.close()                               # the caller's descriptor goes
    writer.queue(wid, batch(7, 64))
    assert writer.flush() == [] and writer.take_sent_bytes() == [(wid, 68)]
    assert sequence_numbers(read_all(reader)) == [7]
    writer.close(wid)                            # the last descriptor: the reader sees EOF
    reader.setblocking(True)
    reader.settimeout(30.0)
    assert reader.recv(10) == b""


def test_a_descriptor_that_cannot_be_duplicated_is_an_os_error(pair):
    sender, _reader = pair
    writer = _core.BatchWriter(1 << 20)
    with pytest.raises(OSError) as bad:
        writer.open(-1)
    assert bad.value.errno == errno.EBADF
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    lowest_free = os.dup(0)
    os.close(lowest_free)
    resource.setrlimit(resource.RLIMIT_NOFILE, (lowest_free, hard))   # no descriptor left
    try:
        with pytest.raises(OSError) as full:
            writer.open(sender.fileno())
        borrowed = writer.open(sender.fileno(), own=False)
    finally:
        resource.setrlimit(resource.RLIMIT_NOFILE, (soft, hard))
    assert full.value.errno == errno.EMFILE
    writer.queue(borrowed, batch(3, 40))
    assert writer.flush() == [] and writer.take_sent_bytes() == [(borrowed, 44)]
    writer.close(borrowed)                       # borrowed: the caller's descriptor stays open
    sender.send(b"")


def test_a_closed_sockets_descriptor_is_refused_borrowed_too():
    writer = _core.BatchWriter(1 << 20)
    with pytest.raises(OSError) as bad:
        writer.open(-1, own=False)           # a closed socket's fileno()
    assert bad.value.errno == errno.EBADF
    assert writer.connection_count == 0


def test_slices_of_one_buffer_go_to_their_connections_in_call_order():
    pairs = [socket.socketpair() for _ in range(2)]
    try:
        writer = _core.BatchWriter(1 << 20)
        ids = [writer.open(a.fileno()) for a, _ in pairs]
        packed = batch(1, 16) + batch(2, 24) + batch(3, 8)       # one step, three messages
        bounds = [(0, 20), (20, 48), (48, 60)]
        writer.queue(ids[0], batch(0, 12))
        # connection 0 gets messages 1 and 3, connection 1 message 2; then a second step
        rows = [(ids[0], *bounds[0]), (ids[1], *bounds[1]), (ids[0], *bounds[2])]
        writer.queue_slices(packed, np.array(rows))
        writer.queue_slices(packed, np.array([(ids[1], *bounds[0])]))
        assert writer.flush() == []
        assert sorted(writer.take_sent_bytes()) == [(ids[0], len(batch(0, 12)) + 20 + 12),
                                                    (ids[1], 28 + 20)]
        streams = [read_all(b) for _, b in pairs]
        assert sequence_numbers(streams[0]) == [0, 1, 3]
        assert sequence_numbers(streams[1]) == [2, 1]
        assert streams[0] == batch(0, 12) + packed[0:20] + packed[48:60]
        # a slice outside the buffer is refused before anything is queued
        with pytest.raises(IndexError):
            writer.queue_slices(packed, np.array([(ids[0], 0, 20), (ids[1], 50, 61)]))
        with pytest.raises(ValueError):
            writer.queue_slices(packed, np.array([ids[0], 0, 20]))
        writer.flush()
        assert read_all(pairs[0][1]) == b"" and read_all(pairs[1][1]) == b""
        writer.close(ids[1])       # a closed connection's slices are dropped
        writer.queue_slices(packed, np.array([(ids[1], 0, 20), (ids[0], 20, 48)]))
        writer.flush()
        assert sequence_numbers(read_all(pairs[0][1])) == [2]
    finally:
        for a, b in pairs:
            a.close()
            b.close()

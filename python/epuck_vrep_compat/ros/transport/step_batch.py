"""Publishing the per-step messages: synchronous publishers and a batch that coalesces writes.

rospy offers two ways to publish, and neither fits a swarm:
* with a ``queue_size`` every message is handed to a writer thread: about 13k messages/s;
* synchronously (``queue_size=None``) every message is one ``sendall`` on its own TCP connection.
  Measured here, one TCP packet to a local subscriber costs about 25 us, so 100 robots x 10
  topics x 20 Hz caps the simulator near real time once someone subscribes to everything.

:class:`StepBatch` keeps rospy's connection management (registration, handshakes, latching,
dead-connection removal) and only takes over the data path: each step's messages are framed
as TCPROS frames and appended per topic; :meth:`StepBatch.flush` writes each topic's frames
with one ``write_data`` per connection. The node flushes before it sleeps (so at ``rtf`` 1 every
step goes out at once, as before) and otherwise at least every ``max_delay_s`` of wall time, so
when the simulation runs faster than the subscribers could take single packets, several steps
share one packet. It relies on ``_PublisherImpl.connections`` / ``remove_connection`` and
``TCPROSTransport.socket``, rospy internals unchanged since ROS Kinetic.

Writes never block: rospy's ``sendall`` would stop the whole simulation as soon as one
subscriber stops reading (a frozen rviz, a process stopped in a debugger) and its socket buffers
fill. Each connection takes what its socket accepts now; the rest waits in that connection's
backlog, retried at every flush, and a backlog above ``max_backlog_bytes`` drops its oldest
whole batches (never a partly sent one), with a throttled warning: a stuck subscriber loses
messages, like a full roscpp subscriber queue, and everyone else keeps the rates.
"""
import collections
import io
import socket
import struct
import time
import warnings

import rospy

_FRAME = struct.Struct("<I")
_WARN_PERIOD_S = 10.0     # wall seconds between warnings about one stuck subscriber


def synchronous_publisher(topic, msg_class, **kwargs):
    """A rospy publisher without a writer thread (``queue_size=None``, deliberately).

    rospy warns about ``queue_size=None`` because it cannot tell a choice from a forgotten
    argument; the per-step topics go through :class:`StepBatch` anyway.
    """
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*explicit keyword argument 'queue_size'.*")
        return rospy.Publisher(topic, msg_class, queue_size=None, **kwargs)


def wire_bytes(msg) -> bytes:
    """The serialised body of a message (pre-serialised ``WireMessage`` or genpy message)."""
    data = getattr(msg, "_bytes", None)
    if data is None:
        buff = io.BytesIO()
        msg.serialize(buff)
        data = buff.getvalue()
    return data


class _Backlog:
    """Bytes a subscriber's socket has not taken yet: whole batches, the first maybe partly
    sent (``chunks`` hold memoryviews)."""
    __slots__ = ("impl", "chunks", "size")

    def __init__(self, impl):
        self.impl = impl
        self.chunks = collections.deque()
        self.size = 0


class StepBatch:
    """Messages of one or more steps, written to the subscribers together."""

    def __init__(self, max_delay_s: float = 0.05, max_backlog_bytes: int = 4 << 20):
        self.max_delay_s = max_delay_s
        self.max_backlog_bytes = max_backlog_bytes
        self._pending = {}            # publisher impl -> list of framed messages
        self._backlogs = {}           # connection -> _Backlog (only while one exists)
        self._dropped = {}            # (subscriber, topic) -> batches dropped so far
        self._warned = {}             # (subscriber, topic) -> wall time of the last warning
        self._last_flush = time.monotonic()

    @staticmethod
    def wanted(pub) -> bool:
        """True when someone subscribes: build the message only then."""
        return bool(pub.impl.connections)

    def add(self, pub, msg):
        """Queue a message (genpy or pre-serialised) for the publisher's subscribers."""
        if pub.impl.connections:
            data = wire_bytes(msg)
            self.add_frame(pub, _FRAME.pack(len(data)) + data)

    def add_frame(self, pub, frame: bytes):
        """Queue an already framed message (4-byte length, then the body)."""
        impl = pub.impl
        if not impl.connections:
            return
        chunks = self._pending.get(impl)
        if chunks is None:
            self._pending[impl] = [frame]
        else:
            chunks.append(frame)

    def due(self) -> bool:
        return time.monotonic() - self._last_flush >= self.max_delay_s

    @property
    def backlog_bytes(self) -> int:
        """Bytes waiting for subscribers that do not keep up."""
        return sum(b.size for b in self._backlogs.values())

    def flush(self):
        pending, self._pending = self._pending, {}
        self._last_flush = time.monotonic()
        for impl, chunks in pending.items():
            if impl.closed:
                continue
            data = b"".join(chunks)
            for connection in impl.connections:     # rospy replaces the list, never mutates it
                backlog = self._backlogs.get(connection)
                if backlog is None:
                    sent = self._send(impl, connection, data)
                    if sent is None or sent == len(data):
                        continue
                    backlog = self._backlogs[connection] = _Backlog(impl)
                    data_left = memoryview(data)[sent:]
                else:
                    data_left = memoryview(data)
                backlog.chunks.append(data_left)
                backlog.size += len(data_left)
                self._trim(connection, backlog)
        if self._backlogs:
            self._drain()

    def _trim(self, connection, backlog):
        """Drop the oldest whole batches after the head while the backlog is too big."""
        dropped = 0
        while backlog.size > self.max_backlog_bytes and len(backlog.chunks) > 1:
            chunk = backlog.chunks[1]
            del backlog.chunks[1]
            backlog.size -= len(chunk)
            dropped += 1
        if not dropped:
            return
        key = (connection.endpoint_id, backlog.impl.resolved_name)
        self._dropped[key] = total = self._dropped.get(key, 0) + dropped
        now = time.monotonic()          # wall time: rospy's throttles follow /clock
        if now - self._warned.get(key, -_WARN_PERIOD_S) >= _WARN_PERIOD_S:
            self._warned[key] = now
            rospy.logwarn("subscriber %s of %s is not reading: %d batches of messages dropped "
                          "for it so far, %.1f MB waiting", key[0], key[1], total,
                          backlog.size / 1e6)

    def _drain(self):
        for connection, backlog in list(self._backlogs.items()):
            impl = backlog.impl
            while backlog.chunks:
                head = backlog.chunks[0]
                sent = None
                if not impl.closed and connection in impl.connections:
                    sent = self._send(impl, connection, head)
                if sent is None:                       # the connection is gone
                    backlog.chunks.clear()
                    break
                backlog.size -= sent
                if sent < len(head):
                    backlog.chunks[0] = head[sent:]
                    break
                backlog.chunks.popleft()
            if not backlog.chunks:
                del self._backlogs[connection]

    @staticmethod
    def _send(impl, connection, data):
        """Bytes the socket took now (0 when full), or None when the connection failed and
        was dropped."""
        sock = connection.socket
        if sock is None or connection.done:
            impl.remove_connection(connection)
            return None
        try:
            sent = sock.send(data, socket.MSG_DONTWAIT)
        except BlockingIOError:
            return 0
        except OSError as e:       # rospy drops a failing connection too
            rospy.logdebug("dropping connection to %s: %s", connection.endpoint_id, e)
            impl.remove_connection(connection)
            connection.close()
            return None
        connection.stat_bytes += sent
        return sent

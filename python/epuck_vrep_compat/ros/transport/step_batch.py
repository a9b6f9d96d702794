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

Writes never block, and they leave the interpreter: the core's ``BatchWriter`` (C++, bound in
``_core``) writes every waiting batch of a connection with one ``sendmsg``, without the GIL, on
its own thread in the node (``background``), while Python prepares the next step. rospy's
``sendall`` would stop the whole simulation as soon as one subscriber stops reading (a frozen
rviz, a process stopped in a debugger) and its socket buffers fill. Each connection takes what
its socket accepts now; the rest waits in that connection's backlog, retried at every flush, and
a backlog above ``max_backlog_bytes`` or ``max_backlog_batches`` drops its oldest whole batches
(never a partly sent one), with a throttled warning: a stuck subscriber loses messages, like a
full roscpp subscriber queue, and everyone else keeps the rates. A batch is one flush's messages
(one step's at real time, up to ``max_delay_s`` of wall time's flat out), so the default of 20
batches lets a subscriber fall about a second behind, beyond what its socket buffers hold,
before it loses the oldest; it also bounds memory when thousands of subscriptions each lag a
little (at 1000 robots with everything subscribed, bytes alone let backlogs reach 2 GB).

The writer writes on rospy's own descriptors (a duplicate each would double the node's
descriptors, 14 001 connections at N = 1000 with everything subscribed, and starve rospy's
accepts at the process's limit). rospy closes a dropped connection from its own threads, always
through the connection's ``close``: that first takes the connection out of the writer, waiting
for a flush under way, so the writer never writes on a descriptor the system may have reused.
A connection rospy forgets otherwise is taken out within ``_SCAN_PERIOD_S`` of wall time.
Latched topics that change now and then go through it too (``latched.py``).
"""
import io
import struct
import time
import warnings

import rospy

from epuck_vrep_compat._core import BatchWriter
from epuck_vrep_compat.ros.transport.latched import LatchedTopics

_FRAME = struct.Struct("<I")
_WARN_PERIOD_S = 10.0     # wall seconds between warnings about one stuck subscriber
_SCAN_PERIOD_S = 0.5      # wall seconds between looks for connections rospy dropped
_DRAIN_POLL_S = 0.005     # wall seconds between offers of the backlogs when the node stops


def synchronous_publisher(topic, msg_class, **kwargs):
    """A rospy publisher without a writer thread (``queue_size=None``, deliberately).

    rospy warns about ``queue_size=None`` because it cannot tell a choice from a forgotten
    argument; the per-step topics go through :class:`StepBatch` anyway.
    """
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*explicit keyword argument 'queue_size'.*")
        return rospy.Publisher(topic, msg_class, queue_size=None, **kwargs)


def _close_through(writer, writer_id, connection):
    """Make the connection's ``close`` take it out of the writer first (rospy closes dropped
    connections from its own threads; the writer must be done with the descriptor)."""
    rospy_close = connection.close

    def close():
        writer.close(writer_id)          # waits for a flush under way; then never again
        rospy_close()
    connection.close = close


def wire_bytes(msg) -> bytes:
    """The serialised body of a message (pre-serialised ``WireMessage`` or genpy message)."""
    data = getattr(msg, "_bytes", None)
    if data is None:
        buff = io.BytesIO()
        msg.serialize(buff)
        data = buff.getvalue()
    return data


class StepBatch:
    """Messages of one or more steps, written to the subscribers together."""

    def __init__(self, max_delay_s: float = 0.05, max_backlog_bytes: int = 4 << 20,
                 max_backlog_batches: int = 20, background: bool = False):
        """``background``: the writer's own thread sends each flush while the caller goes on
        (the simulator node); otherwise :meth:`flush` sends before it returns."""
        self.max_delay_s = max_delay_s
        self._background = background
        self.max_backlog_bytes, self.max_backlog_batches = max_backlog_bytes, max_backlog_batches
        self._pending = {}            # publisher impl -> list of framed messages
        self._writer = BatchWriter(max_backlog_bytes, max_backlog_batches)
        self._ids = {}                # connection -> (writer id, publisher impl)
        self._by_id = {}              # writer id -> connection
        self._dropped = {}            # subscriber -> batches dropped for it so far
        self._lagging = {}            # subscriber -> its topics with drops since its warning
        self._warned = {}             # subscriber -> wall time of its last warning
        self._latched = LatchedTopics()
        self._last_flush = self._last_scan = time.monotonic()

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

    def latched_publisher(self, topic, msg_class):
        """A latched topic whose messages go through :meth:`add_latched`: a new subscriber
        gets the last one at the next flush (``latched.py``)."""
        return self._latched.publisher(topic, msg_class, synchronous_publisher)

    def add_latched(self, pub, msg):
        """Queue a message of a :meth:`latched_publisher`'s topic and keep it for the topic's
        later subscribers."""
        data = wire_bytes(msg)
        frame = _FRAME.pack(len(data)) + data
        self._latched.keep(pub.impl, frame)
        self.add_frame(pub, frame)

    def add_slices(self, data: bytes, slices):
        """Queue slices of one packed buffer, each for one connection: rows (writer id, begin,
        end) of ``slices``, ids from :meth:`writer_id`. A face whose messages of one kind lie
        in one buffer sends a step of them in one call, however many topics they go to."""
        if len(slices):
            self._writer.queue_slices(data, slices)

    def writer_id(self, pub, connection):
        """The writer's id for one of ``pub``'s connections (opened on first use), or None
        when rospy has dropped the connection meanwhile. For :meth:`add_slices`' tables, which
        a face rebuilds when its topics' connections change."""
        entry = self._entry(pub.impl, connection)
        return None if entry is None else entry[0]

    def due(self) -> bool:
        return time.monotonic() - self._last_flush >= self.max_delay_s

    @property
    def backlog_bytes(self) -> int:
        """Bytes waiting for subscribers that do not keep up."""
        return self._writer.backlog_bytes

    def flush(self):
        """Queue each topic's batch for each of its connections, then write them all at once
        (in C++, without the GIL, never blocking)."""
        pending, self._pending = self._pending, {}
        now = self._last_flush = time.monotonic()
        writer = self._writer
        self._queue_latched()                       # before anything newer on those topics
        for impl, chunks in pending.items():
            if impl.closed:
                continue
            data = b"".join(chunks)
            for connection in impl.connections:     # rospy replaces the list, never mutates it
                entry = self._entry(impl, connection)
                if entry is not None:
                    writer.queue(entry[0], data)
        self._latched.sent()
        if now - self._last_scan >= _SCAN_PERIOD_S:
            self._last_scan = now
            self._forget_gone()
            self._count_sent(wait=False)     # not while the writer's thread flushes
        if self._background:
            writer.request_flush()
            self._apply(writer.take_reports(False))     # of the flushes done meanwhile
        else:
            self._apply(writer.flush())

    def _queue_latched(self):
        """A joined latched topic's last frame for each connection new to the writer."""
        for impl, frame in self._latched.joined():
            for connection in impl.connections:
                if connection not in self._ids:
                    entry = self._open(impl, connection)
                    if entry is not None:
                        self._writer.queue(entry[0], frame)

    def settle(self):
        """Wait until the writer's thread has sent every flush requested so far (and count
        what it sent)."""
        self._apply(self._writer.take_reports(True))
        self._count_sent(wait=True)

    def drain(self, timeout_s: float):
        """The node stops: send what is queued, then offer lagging subscribers their backlogs
        for up to ``timeout_s`` of wall time, so that a recorder gets the last steps."""
        self.flush()
        self.settle()
        deadline = time.monotonic() + timeout_s
        while self._writer.backlog_bytes and time.monotonic() < deadline:
            time.sleep(_DRAIN_POLL_S)
            self._apply(self._writer.flush())    # the writer's thread is idle after settle()

    def _count_sent(self, wait: bool):
        """Add what the writer sent since the last count to each connection's ``stat_bytes``
        (rospy's bus statistics): every ``_SCAN_PERIOD_S``, not every flush, which at 14 000
        connections would cost the step loop a Python loop over all of them."""
        by_id = self._by_id
        for writer_id, sent in self._writer.take_sent_bytes(wait):
            connection = by_id.get(writer_id)
            if connection is not None:
                connection.stat_bytes += sent

    def _apply(self, reports):
        """Follow the writer's reports (only where something went wrong): drops warned
        about, failures dropped."""
        for writer_id, dropped, failed in reports:
            connection = self._by_id.get(writer_id)
            if connection is None:       # forgotten since that flush
                continue
            impl = self._ids[connection][1]
            if dropped:
                self._warn_dropped(connection, impl, dropped)
            if failed:                   # rospy drops a failing connection too
                rospy.logdebug("dropping connection to %s", connection.endpoint_id)
                self._forget(connection)
                _remove_connection(impl, connection)
                connection.close()

    def _entry(self, impl, connection):
        """The writer's (id, impl) for a connection, opened on first use; None: it is gone."""
        entry = self._ids.get(connection)
        return entry if entry is not None else self._open(impl, connection)

    def _open(self, impl, connection):
        """The writer's entry for a connection seen for the first time (None: it is gone)."""
        sock = connection.socket
        fd = -1 if sock is None else sock.fileno()       # -1: closed meanwhile
        if fd < 0 or connection.done:
            _remove_connection(impl, connection)
            return None
        writer_id = self._writer.open(fd, own=False)
        _close_through(self._writer, writer_id, connection)
        entry = self._ids[connection] = (writer_id, impl)
        self._by_id[writer_id] = connection
        if connection.done or connection.socket is not sock:
            # rospy closed it between the check and _close_through (its own close, not ours):
            # the descriptor may be reused, so the writer lets it go before anything is queued
            self._forget(connection)
            _remove_connection(impl, connection)
            return None
        return entry

    def _forget(self, connection):
        writer_id, _impl = self._ids.pop(connection)
        del self._by_id[writer_id]
        self._writer.close(writer_id)

    def _forget_gone(self):
        """Close the writer's side of connections rospy no longer lists."""
        for connection, (_id, impl) in list(self._ids.items()):
            if impl.closed or connection.done or connection not in impl.connections:
                self._forget(connection)
        self._latched.forget_closed()

    def _warn_dropped(self, connection, impl, dropped):
        """One warning per subscriber every ``_WARN_PERIOD_S`` at most, naming its topics
        that lost batches since the last one: a ``rosbag record -a`` falling behind at 1000
        robots lags on thousands of topics, and a line per topic would flood the log."""
        key = connection.endpoint_id
        self._dropped[key] = total = self._dropped.get(key, 0) + dropped
        self._lagging.setdefault(key, set()).add(impl.resolved_name)
        now = time.monotonic()          # wall time: rospy's throttles follow /clock
        if now - self._warned.get(key, -_WARN_PERIOD_S) >= _WARN_PERIOD_S:
            self._warned[key] = now
            topics = sorted(self._lagging.pop(key))
            shown = ", ".join(topics[:3]) + (", ..." if len(topics) > 3 else "")
            rospy.logwarn("subscriber %s is not reading: %d batches of messages dropped for it "
                          "so far, lately on %d topic(s) (%s); %.1f MB waiting in all", key,
                          total, len(topics), shown, self._writer.backlog_bytes / 1e6)


def _remove_connection(impl, connection):
    """rospy's ``remove_connection``, unless the topic was closed meanwhile (a robot removed, the
    node shutting down): rospy's ``close`` sets its connection list to None, and removing from
    it would raise in the step loop."""
    if not impl.closed and impl.connections is not None:
        impl.remove_connection(connection)

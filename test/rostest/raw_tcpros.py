"""A subscriber that speaks TCPROS itself, for tests that open many connections at once.

rospy's and roscpp's subscribers register with the master and connect one topic at a time;
this one connects straight to a node's TCPROS server with a non-blocking socket per topic, so
that all its connections arrive together (as ``rosbag record -a`` or rqt make them), at a
cost of a few microseconds each in the test process.
"""
import selectors
import socket
import struct
import time
import xmlrpc.client


def tcpros_header(fields):
    body = b"".join(struct.pack("<I", len(f)) + f for f in
                    (f"{k}={v}".encode() for k, v in fields.items()))
    return struct.pack("<I", len(body)) + body


class RawSubscriber:
    """One TCPROS subscription on a non-blocking socket: its header sent, its bytes counted;
    ``closed``: the publisher closed the connection (end of file read)."""

    CALLER_ID = "/test_subscribe_everything_raw"

    def __init__(self, topic, address):
        self.topic = topic
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.sock.setblocking(False)
        self.sock.connect_ex(address)           # in flight: every connection at once
        self.header = tcpros_header({"callerid": self.CALLER_ID, "topic": topic, "md5sum": "*",
                                     "type": "*", "tcp_nodelay": "1"})
        self.buffer = b""
        self.messages = 0
        self.sent = False
        self.closed = False

    def send_header(self):
        try:
            self.sock.sendall(self.header)
            self.sent = True
        except BlockingIOError:
            pass

    def read(self):
        """Take what arrived; count whole messages after the publisher's header."""
        try:
            data = self.sock.recv(1 << 16)
        except BlockingIOError:
            return
        except ConnectionResetError:
            data = b""
        if not data:
            self.closed = True
            return
        self.buffer += data
        while len(self.buffer) >= 4:
            size = struct.unpack("<I", self.buffer[:4])[0]
            if len(self.buffer) < 4 + size:
                break
            self.buffer = self.buffer[4 + size:]
            self.messages += 1                  # the first frame is the publisher's header


def subscribe_all(topics, address, timeout_s):
    """A :class:`RawSubscriber` for each topic, all connecting at once to the TCPROS server at
    ``address``, each header sent once its socket is writable (within ``timeout_s``: liveness
    only). Uses epoll, not ``select``: a test at 100 robots holds more than 1024 sockets."""
    subs = {t: RawSubscriber(t, address) for t in topics}
    deadline = time.monotonic() + timeout_s
    with selectors.DefaultSelector() as selector:
        for sub in subs.values():
            selector.register(sub.sock, selectors.EVENT_WRITE, sub)
        while time.monotonic() < deadline and any(not s.sent for s in subs.values()):
            for key, _events in selector.select(0.2):
                key.data.send_header()
                if key.data.sent:
                    selector.unregister(key.fileobj)
    return subs


def pump(subs, until, timeout_s):
    """Read every open subscription until ``until()`` holds or ``timeout_s`` has passed."""
    deadline = time.monotonic() + timeout_s
    with selectors.DefaultSelector() as selector:
        for sub in subs.values():
            if not sub.closed:
                selector.register(sub.sock, selectors.EVENT_READ, sub)
        while not until() and time.monotonic() < deadline:
            for key, _events in selector.select(0.1):
                key.data.read()
                if key.data.closed:
                    selector.unregister(key.fileobj)


def tcpros_address(node_uri, topic):
    """(host, port) of the TCPROS server of the node at ``node_uri`` (one serves every topic
    of a node), from its answer to ``requestTopic``."""
    code, msg, protocol = xmlrpc.client.ServerProxy(node_uri).requestTopic(
        RawSubscriber.CALLER_ID, topic, [["TCPROS"]])
    assert code == 1, msg
    return protocol[1], protocol[2]

"""Room for connections in rospy's servers, so that no subscriber's connection is lost.

A subscriber that takes many topics at once (``rosbag record -a``, rqt, a benchmark's
``subscribe_all``) first asks the node for each topic over XML-RPC (``requestTopic``), then
opens one TCPROS connection per topic, all within milliseconds. rospy's TCPROS server (every
topic and service of the node shares it) listens with a queue of 5 connections not yet
accepted, its XML-RPC server with 128, and each accepts from one Python thread. While the
simulation runs flat out those threads get the interpreter only now and then, the queues
overflow, and Linux drops the handshake of every connection beyond them; the subscriber's side
then waits for TCP's retransmissions (1 s, 3 s, 7 s, ...), or, for TCPROS, counts the
connection as open when the node never saw it. Measured: 50 of 132 topics silent for more
than 15 s at 10 robots (TCPROS); at 1000 robots, 100 000 dropped XML-RPC connection attempts
in 70 s.

:func:`widen_accept_queue` lets the kernel hold them instead (Linux caps a queue at
``net.core.somaxconn``, 4096 by default), so each waits its turn to be accepted. It relies on
rospy's ``tcpros_base`` server objects and on the XML-RPC node rospy registers as a shutdown
hook, both unchanged since ROS Kinetic.

Descriptors run out before the queues do. rospy gives every topic of a node its own ``epoll``
descriptor (``topics.Poller``, to notice dead connections), so 1000 robots' 15 000 topics hold
15 000 descriptors before anyone subscribes (more than the usual soft limit of 1024 at 100
robots), and with a limit of 20 000 the node ran out after about 5 000 subscriptions. rospy's TCPROS accept thread then died on ``EMFILE`` and the
node never accepted another connection, to a topic or a service, for the rest of its life.
:func:`share_connection_poller` (before the node makes its topics) gives all topics one
``epoll`` (the kernel keeps one registration per descriptor, and a dead connection's events
stay until it is removed, so each topic still finds its own), :func:`raise_descriptor_limit`
lifts the soft limit to the hard one, and :func:`widen_accept_queue` also keeps the accept
thread alive through a full descriptor table (it logs, waits and retries).

When the node stops, :func:`stop_accepting` shuts the TCPROS listening socket first: rospy
would go on accepting and handshaking new connections (taking its topic manager's lock for
each) while it closes the topics, and a subscriber to everything kept a stopping node busy for
seconds. Connections not yet accepted are refused; the thread blocked in ``accept`` ends.
"""
import errno
import resource
import socket
import threading
import time

import rosgraph.xmlrpc
import rospy
import rospy.core
import rospy.topics
from rospy.impl import tcpros_base

ACCEPT_QUEUE = 4096
_FULL_TABLE_WAIT_S = 0.1   # accept again after this long when the descriptor table is full
_WARN_PERIOD_S = 10.0


def share_connection_poller():
    """Make every rospy topic created from now on share one dead-connection poller (one
    ``epoll`` descriptor in all, instead of one per topic)."""
    shared = rospy.topics.Poller()
    rospy.topics.Poller = lambda: shared


def raise_descriptor_limit() -> int:
    """Lift the soft limit on open descriptors to the hard limit; returns the limit now."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft != hard:
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))
            soft = hard
        except (ValueError, OSError) as e:
            rospy.logwarn("cannot raise the open-descriptor limit from %d to %d: %s", soft,
                          hard, e)
    return soft


class _SurvivingListener:
    """rospy's TCPROS listening socket, whose ``accept`` waits and retries while the
    descriptor table is full instead of raising (which ends rospy's accept thread)."""

    def __init__(self, sock):
        self._sock = sock
        self._warned_at = -_WARN_PERIOD_S

    def accept(self):
        while True:
            try:
                return self._sock.accept()
            except OSError as e:
                if e.errno not in (errno.EMFILE, errno.ENFILE):
                    raise
                now = time.monotonic()
                if now - self._warned_at >= _WARN_PERIOD_S:
                    self._warned_at = now
                    rospy.logerr("no descriptor left for a new connection (limit %d): "
                                 "connections wait until others close",
                                 resource.getrlimit(resource.RLIMIT_NOFILE)[0])
                time.sleep(_FULL_TABLE_WAIT_S)

    def __getattr__(self, name):
        return getattr(self._sock, name)


def _tcpros_server():
    tcpros_base.start_tcpros_server()          # rospy starts it lazily, with the first topic
    handler = getattr(tcpros_base, "_tcpros_server", None)
    return getattr(handler, "tcp_ros_server", None)


def _tcpros_socket():
    sock = getattr(_tcpros_server(), "server_sock", None)
    return sock._sock if isinstance(sock, _SurvivingListener) else sock


def _xmlrpc_socket():
    for hook in getattr(rospy.core, "_shutdown_hooks", []):
        node = getattr(hook, "__self__", None)   # init_node registers node.shutdown
        if isinstance(node, rosgraph.xmlrpc.XmlRpcNode) and node.server is not None:
            return node.server.socket
    return None


def widen_accept_queue(backlog: int = ACCEPT_QUEUE) -> bool:
    """After ``init_node``: let the listening sockets of rospy's TCPROS and XML-RPC servers
    queue ``backlog`` connections each, and the TCPROS one survive a full descriptor table;
    False (logged) when rospy has no such socket."""
    server = _tcpros_server()
    if server is not None and server.server_sock is not None and \
            not isinstance(server.server_sock, _SurvivingListener):
        server.server_sock = _SurvivingListener(server.server_sock)
    widened = True
    for server, find in (("TCPROS", _tcpros_socket), ("XML-RPC", _xmlrpc_socket)):
        sock = find()
        if sock is None:
            rospy.logwarn("rospy's %s server has no listening socket; its accept queue stays "
                          "as rospy made it, and a subscriber to many topics at once may wait",
                          server)
            widened = False
            continue
        sock.listen(backlog)                   # on a listening socket: a new queue length
    return widened



def handshake_in_own_thread() -> bool:
    """After ``init_node``: each accepted TCPROS connection's handshake runs in a thread of its
    own. rospy's accept thread reads a new connection's header itself, with no time-out, so one
    client that connects and then stalls (a stopped or starved subscriber, re-notified of this
    node) kept every later subscriber from connecting: after a respawn beside a CPU hog, a
    subscriber waited 60 s in vain. False when rospy has no TCPROS server."""
    server = _tcpros_server()
    if server is None or getattr(server, "_evc_threaded", False):
        return server is not None
    handler = server.inbound_handler

    def spawn(sock, addr):
        threading.Thread(target=handler, args=(sock, addr), daemon=True,
                         name="tcpros-handshake").start()
    server.inbound_handler, server._evc_threaded = spawn, True
    return True


def stop_accepting():
    """The node stops: no more TCPROS connections (topics and services). The listening socket
    is shut down, not only closed, so that the thread blocked in its ``accept`` wakes and ends;
    a subscriber that asks for a topic now (XML-RPC answers until the node ends) is refused."""
    server = getattr(getattr(tcpros_base, "_tcpros_server", None), "tcp_ros_server", None)
    sock = _tcpros_socket() if server is not None else None
    if sock is None:
        return
    server.is_shutdown = True          # its accept loop ends instead of raising
    try:
        sock.shutdown(socket.SHUT_RDWR)
    except OSError:                    # closed already
        pass

"""A deeper accept queue for rospy's TCPROS server, so that no subscriber's connection is lost.

rospy's TCPROS server (every topic and service of the node shares it) listens with a queue of
5 connections not yet accepted, and accepts them from one Python thread. A subscriber that
takes many topics at once (``rosbag record -a``, rqt, a benchmark's ``subscribe_all``) opens
one connection per topic within milliseconds; while the simulation runs flat out, that thread
gets the interpreter only now and then, the queue overflows, and Linux drops the handshake of
every connection beyond it. The subscriber's side counts such a connection as open and has
sent its header, the node never sees it, and the topic delivers nothing to that subscriber for
as long as TCP's retransmissions take to give up (measured: 50 of 132 topics silent for more
than 15 s at 10 robots). :func:`widen_accept_queue` lets the kernel hold them instead (Linux
caps the queue at ``net.core.somaxconn``, 4096 by default), so each waits its turn to be
accepted. It relies on rospy's ``tcpros_base`` server objects, unchanged since ROS Kinetic.
"""
import rospy
from rospy.impl import tcpros_base

ACCEPT_QUEUE = 4096


def widen_accept_queue(backlog: int = ACCEPT_QUEUE) -> bool:
    """Start rospy's TCPROS server if it has not started yet and let its listening socket
    queue ``backlog`` connections; False (logged) when rospy has no such socket."""
    tcpros_base.start_tcpros_server()          # rospy starts it lazily, with the first topic
    handler = getattr(tcpros_base, "_tcpros_server", None)
    server = getattr(handler, "tcp_ros_server", None)
    sock = getattr(server, "server_sock", None)
    if sock is None:
        rospy.logwarn("rospy's TCPROS server has no listening socket; its accept queue stays "
                      "at 5 connections, and a subscriber to many topics at once may wait")
        return False
    sock.listen(backlog)                       # on a listening socket: a new queue length
    return True

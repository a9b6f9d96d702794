"""Stopping the simulator node in seconds at any size, whoever is subscribed.

rospy's own way out of a node (its SIGINT handler calling ``signal_shutdown`` in the middle of
whatever the main thread does) took 7-18 s at 1000 robots with one subscriber to everything:
its clean-up waits for the master to unregister every topic, then closes topic after topic
under its topic manager's lock while its TCPROS server goes on accepting and handshaking the
connections a subscriber keeps opening, and a dead-connection check running meanwhile on a
closed topic raised a ``TypeError`` in ``remove_connection``. roslaunch escalates to SIGTERM
after 15 s and to SIGKILL after 2 more, and a bag recorded through the stop lost its end.

Here SIGINT and SIGTERM only ask the step loop to stop (:class:`StopRequest`); the loop ends
after the step under way, and :func:`stop_node` then, on the main thread and under the
simulation's lock (no ``~step`` or ``/vrep`` call publishes meanwhile):

1. refuses new TCPROS connections (``accept_queue.stop_accepting``), and switches off rospy's
   periodic connection check, so no thread touches a topic about to close;
2. sends what the last steps published (``StepBatch.drain``): a recorder gets every step up to
   the stop;
3. hands every registration's withdrawal to a process of its own that sends them to the master
   in ``system.multicall`` batches (``registration.withdraw_all``, ``transport/withdraw.py``:
   the master needs about 0.5 ms for each, so some 7-9 s for 1000 robots' 18 000, which the
   node does not wait for), after start-up's bulk registration has stopped; rospy is left nothing to unregister;
4. closes every connection and topic once (rospy's topic manager), so that each subscriber
   reads to the end of what was sent (a process that ends with data unread on a socket resets
   the connection instead);
5. flushes its logs and ends the process with status :data:`EXIT_STOPPED` (0) without the
   interpreter's teardown, which frees every topic, connection and core object one by one (2.3 s
   at 100 robots with everything subscribed) for a process that is ending anyway.

A second signal while it stops changes nothing. It relies on rospy's topic and service
managers, unchanged since ROS Kinetic.
"""
import logging
import os
import signal
import sys
import threading

import rospy
from rospy.impl.registration import get_service_manager, get_topic_manager

from epuck_vrep_compat.ros.transport.accept_queue import stop_accepting
from epuck_vrep_compat.ros.transport.registration import withdraw_all

EXIT_STOPPED = 0
DRAIN_S = 0.5        # wall seconds at most to hand the last steps to slow subscribers


class StopRequest:
    """SIGINT and SIGTERM set :attr:`signal_name`; the step loop polls :meth:`requested`.
    Install after ``rospy.init_node(..., disable_signals=True)``."""

    def __init__(self):
        self._event = threading.Event()
        self.signal_name = None
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, self._on_signal)

    def _on_signal(self, signum, _frame):
        if self.signal_name is None:
            self.signal_name = signal.Signals(signum).name
        self._event.set()

    def requested(self) -> bool:
        return self._event.is_set()


def stop_node(batch, lock, registration, reason: str):
    """Everything after the last step (see the module's text); ends the process.
    ``batch``: the node's ``StepBatch``, used under ``lock`` (the simulation's: a ``~step``
    service call may still be sending); ``registration``: start-up's ``BulkRegistration``."""
    stop_accepting()
    topics = get_topic_manager()
    topics.check_all = lambda: None          # rospy's connection checks: nothing to check now
    with lock:                               # no step or service publishes from here on
        batch.drain(DRAIN_S)
        registration.close()
        withdrawn = withdraw_all()
        rospy.loginfo("epuck_sim stops (%s): %d registrations handed over to be withdrawn "
                      "from the master", reason, withdrawn)
        # rospy writes a line to its log file for every connection it removes: at 100 robots
        # with everything subscribed, three quarters of closing them
        logging.getLogger("rospy.internal").setLevel(logging.WARNING)
        topics.close_all()                   # every connection, once
        get_service_manager().unregister_all()
        logging.shutdown()                   # rospy's log file and console handlers
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(EXIT_STOPPED)

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

A second signal while it stops changes nothing. rospy's own shutdown (``rosnode kill``, which
calls the node's XML-RPC ``shutdown``; a registration the master refuses) is a request like a
signal once the step loop runs (:meth:`StopRequest.hold_rospy_shutdown`): rospy's clean-up,
which would unregister and close everything on its own thread while the stop does the same,
never starts. However the loop or the stop ends, even by an exception, the process ends at once
(:func:`end_process`): the interpreter's teardown would run rospy's shutdown after all, through
its ``atexit`` hook. It relies on rospy's topic and service managers, unchanged since ROS
Kinetic.
"""
import logging
import os
import signal
import sys
import threading
import traceback

import rospy
from rospy.impl.registration import get_service_manager, get_topic_manager

from epuck_vrep_compat.ros.transport.accept_queue import stop_accepting
from epuck_vrep_compat.ros.transport.registration import withdraw_all

EXIT_STOPPED = 0
EXIT_FAILED = 1      # the step loop or the stop raised (logged with its traceback)
SHUTDOWN_REQUEST = "shutdown request"      # rospy's own shutdown, named as a signal is
DRAIN_S = 0.5        # wall seconds at most to hand the last steps to slow subscribers


class StopRequest:
    """SIGINT and SIGTERM (and, once held, rospy's own shutdown) set :attr:`signal_name`; the
    step loop polls :meth:`requested`. Install after ``rospy.init_node(...,
    disable_signals=True)``."""

    def __init__(self):
        self._event = threading.Event()
        self.signal_name = None
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, self._on_signal)

    def _on_signal(self, signum, _frame):
        self._request(signal.Signals(signum).name)

    def _request(self, name: str):
        if self.signal_name is None:
            self.signal_name = name
        self._event.set()

    def requested(self) -> bool:
        return self._event.is_set()

    def hold_rospy_shutdown(self):
        """From now on rospy's own shutdown requests the stop and goes no further: its first
        hooks (``rospy.on_shutdown``'s, before its registration clean-up) hold the thread that
        called it until :func:`stop_node` ends the process. Call right before the step loop,
        after which every way out is :func:`stop_node` (else an ending interpreter would wait
        for the held hook forever)."""
        rospy.on_shutdown(self._on_rospy_shutdown)

    def _on_rospy_shutdown(self):
        self._request(SHUTDOWN_REQUEST)
        threading.Event().wait()          # never set: the process ends under this thread


def stop_node(batch, lock, registration, reason: str, status: int = EXIT_STOPPED):
    """Everything after the last step (see the module's text); ends the process with
    ``status`` (:data:`EXIT_FAILED` if the stop raises). ``batch``: the node's ``StepBatch``,
    used under ``lock`` (the simulation's: a ``~step`` service call may still be sending);
    ``registration``: start-up's ``BulkRegistration``."""
    end_process(lambda: _stop(batch, lock, registration, reason), status)


def _stop(batch, lock, registration, reason: str):
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


def end_process(work, status: int = EXIT_STOPPED, finish=None):
    """Run ``work``, then end the process at once with ``status``, or :data:`EXIT_FAILED`
    with a FATAL line and the traceback when ``work`` raised. ``finish(status)`` ends it
    (default: flush the logs and ``os._exit``; tests pass their own)."""
    try:
        work()
    except BaseException:  # noqa: BLE001 - the process ends either way, and says why
        status = EXIT_FAILED
        rospy.logfatal("epuck_sim: stopping failed, exiting with status %d:\n%s", status,
                       traceback.format_exc())
    finally:
        (finish or _exit_now)(status)


def _exit_now(status: int):
    """Flush rospy's log file and console handlers and the standard streams, then end the
    process without the interpreter's teardown."""
    try:
        logging.shutdown()
        sys.stdout.flush()
        sys.stderr.flush()
    finally:
        os._exit(status)

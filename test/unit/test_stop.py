"""How the simulator node's stop ends the process (``ros/node/stop.py``), without a master: the
process ends with the status asked, or with a failure status when the stop raised (never through
the interpreter's teardown, whose ``atexit`` hook would run rospy's own shutdown after all), and
rospy's own shutdown, once held, requests the stop and goes no further."""
import signal
import threading

import pytest

from epuck_vrep_compat.ros.node import stop


class Exit:
    """Stands in for ``os._exit``: records the status."""

    def __init__(self):
        self.statuses = []

    def __call__(self, status):
        self.statuses.append(status)


def test_the_process_ends_with_the_status_asked_after_the_stop():
    done, exit_ = [], Exit()
    stop.end_process(lambda: done.append(True), stop.EXIT_STOPPED, exit_)
    assert done == [True] and exit_.statuses == [stop.EXIT_STOPPED]
    stop.end_process(lambda: None, stop.EXIT_FAILED, exit_)        # the loop had failed
    assert exit_.statuses[-1] == stop.EXIT_FAILED


def test_a_stop_that_raises_still_ends_the_process_with_a_failure_status():
    exit_ = Exit()

    def broken():
        raise OSError("no descriptor left to start the withdrawal")
    stop.end_process(broken, stop.EXIT_STOPPED, exit_)
    assert exit_.statuses == [stop.EXIT_FAILED]
    assert stop.EXIT_FAILED != stop.EXIT_STOPPED


@pytest.fixture
def request_():
    """A StopRequest, the test process's own signal handlers back afterwards."""
    saved = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    yield stop.StopRequest()
    for sig, handler in saved.items():
        signal.signal(sig, handler)


def test_the_first_signal_names_the_stop(request_):
    assert not request_.requested()
    request_._on_signal(signal.SIGTERM, None)
    request_._on_signal(signal.SIGINT, None)
    assert request_.requested() and request_.signal_name == "SIGTERM"


def test_rospy_shutdown_requests_the_stop_and_holds_its_thread(request_):
    # the hook is called directly: registered in this process, rospy's atexit would call it
    held = threading.Thread(target=request_._on_rospy_shutdown, daemon=True)
    held.start()
    while not request_.requested():
        held.join(0.01)
    assert request_.signal_name == stop.SHUTDOWN_REQUEST
    held.join(0.2)
    assert held.is_alive(), "rospy's shutdown went on to its own clean-up"

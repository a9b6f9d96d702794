"""The TCPROS listener survives a full descriptor table: rospy's accept thread would die on
EMFILE and the node would never accept another connection."""
import errno

import pytest

from epuck_vrep_compat.ros.transport import accept_queue


class FullThenFree:
    """A listening socket whose accept fails ``failures`` times with ``code``, then works."""

    def __init__(self, failures, code):
        self.failures, self.code, self.calls = failures, code, 0

    def accept(self):
        self.calls += 1
        if self.calls <= self.failures:
            raise OSError(self.code, "full")
        return "client", ("127.0.0.1", 1)

    def getsockname(self):
        return ("0.0.0.0", 4242)


@pytest.fixture
def waits(monkeypatch):
    slept, logged = [], []
    monkeypatch.setattr(accept_queue.time, "sleep", slept.append)
    monkeypatch.setattr(accept_queue.rospy, "logerr", lambda *a: logged.append(a))
    return slept, logged


@pytest.mark.parametrize("code", [errno.EMFILE, errno.ENFILE])
def test_a_full_table_is_waited_out_and_logged_once(waits, code):
    slept, logged = waits
    sock = FullThenFree(3, code)
    listener = accept_queue._SurvivingListener(sock)
    assert listener.accept() == ("client", ("127.0.0.1", 1))
    assert sock.calls == 4 and len(slept) == 3 and len(logged) == 1
    assert listener.getsockname() == ("0.0.0.0", 4242)     # everything else is the socket's


def test_other_errors_still_end_the_accept(waits):
    listener = accept_queue._SurvivingListener(FullThenFree(1, errno.EBADF))
    with pytest.raises(OSError):
        listener.accept()

"""The experiment tier: the experiment runner end to end, with real roslaunch, real masters
(each run's roslaunch starts its own) and real Dask. The tests start no master themselves.

Every test runs under ``no_process_left``: it gives the test a token of its own in the
environment (inherited by the CLI, Dask's workers, the shepherds, roslaunch, the masters and
the nodes), snapshots this user's processes (pid and start time, so a reused pid is a new
process), and after the test waits up to ``LEFT_GRACE_S`` for every process started during
the test and carrying the token (or descending from pytest) to be gone; zombies count as gone.
What is left fails the test with its command lines, and is then killed (by pid: it is the
test's own) so that the next test starts clean.
"""
import os
import signal
import sys
import time
import uuid

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import evc_harness as h  # noqa: E402

LEFT_GRACE_S = 20.0


@pytest.fixture(autouse=True)
def no_process_left(monkeypatch):
    token = uuid.uuid4().hex
    monkeypatch.setenv(h.TOKEN, token)
    before = {p.ident for p in h.processes().values()}
    yield token
    deadline = time.monotonic() + LEFT_GRACE_S
    while True:
        left = h.tests_processes(token, before=before)
        if not left or time.monotonic() > deadline:
            break
        time.sleep(0.2)
    if left:
        lines = [f"  pid {p.pid} (parent {p.ppid}, state {p.state}): {p.cmdline()[:300]}"
                 for p in left]
        for p in left:
            try:
                os.kill(p.pid, signal.SIGKILL)
            except OSError:
                pass
        pytest.fail(f"{len(left)} process(es) started by the test still running "
                    f"{LEFT_GRACE_S:g} s after it:\n" + "\n".join(lines), pytrace=False)


@pytest.fixture
def token(no_process_left):
    """This test's process token (see ``no_process_left``)."""
    return no_process_left

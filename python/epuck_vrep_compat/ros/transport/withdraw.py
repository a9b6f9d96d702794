"""Withdrawing a stopping node's registrations from the master, in a process of its own.

The master takes about half a millisecond for each unregistration, however they are sent
(measured on this project's machine: 3 000 ``unregisterPublisher`` in one
``system.multicall`` took 1.2-1.8 s; each one locks, updates, logs and notifies subscribers).
At 1000 robots a node holds about 18 000 registrations: 7-9 s of the master's time, which the
node would spend waiting before it could exit. So the stopping node writes the calls to a file
and starts this module as a process of its own session (:func:`hand_off`); the node exits at
once, and this process sends the calls in ``system.multicall`` batches, waits for the master's
answers and ends (quietly: nobody reads its output; a master that has gone has nothing left
to withdraw, and one that does not answer a batch within ``ANSWER_S`` is left as it is). Unregistrations name the stopped node's own URIs, so they never remove the
registrations of a node started meanwhile under the same name.

Standard library only: it runs in a fresh interpreter, and the less it imports the sooner the
master hears from it.
"""
import json
import os
import socket
import subprocess
import sys
import tempfile
import xmlrpc.client

BATCH = 2000        # calls in one multicall: the master answers each batch in about 1 s
ANSWER_S = 30.0     # a master that answers no batch within this is left as it is


def multicall(master, calls):
    """Send ``calls`` ((method, args) each) in one ``system.multicall``; the answers in order.
    ``master``: an XML-RPC proxy (or a fake with ``system.multicall``). Raises when it does not
    answer."""
    batch = xmlrpc.client.MultiCall(master)
    for method, args in calls:
        getattr(batch, method)(*args)
    return list(batch())


def send(master, calls, batch_size: int = BATCH) -> int:
    """Send ``calls`` in batches until done or the master stops answering; how many were
    answered."""
    answered = 0
    for begin in range(0, len(calls), batch_size):
        part = calls[begin:begin + batch_size]
        try:
            multicall(master, part)
        except (OSError, xmlrpc.client.Error):
            break
        answered += len(part)
    return answered


def hand_off(master_uri: str, calls) -> int:
    """Start a process that sends ``calls`` to the master at ``master_uri`` and ends; its pid.
    It runs in a session of its own, so that the process-group signals that end the node (as
    roslaunch sends them) leave it be."""
    fd, path = tempfile.mkstemp(prefix="epuck_sim_withdraw_", suffix=".json")
    with os.fdopen(fd, "w") as f:
        json.dump({"master_uri": master_uri, "calls": calls}, f)
    try:
        process = subprocess.Popen([sys.executable, "-m", __name__, path],
                                   stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.DEVNULL, start_new_session=True)
    except OSError:          # no process (a full descriptor table): nobody would remove it
        os.unlink(path)
        raise
    return process.pid


def main(path: str):
    with open(path) as f:
        spec = json.load(f)
    os.unlink(path)
    socket.setdefaulttimeout(ANSWER_S)     # never outlive a master that stopped answering
    send(xmlrpc.client.ServerProxy(spec["master_uri"]), [tuple(c) for c in spec["calls"]])


if __name__ == "__main__":
    main(sys.argv[1])

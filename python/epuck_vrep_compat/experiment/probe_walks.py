"""Several runs (walks) in one launch: what the ``experiment_probe`` does between two of them.

The runner gives the probe ``~walks``, one ``{seed, out}`` per run of the chunk, the first
being the launch's own seed. After a walk's recording is written the probe makes the launch
as it was at its start, with the next seed:

1. ``/vrep/rewind`` (:mod:`epuck_vrep_compat.ros.node.rewind`): the simulation paused at time
   0, reseeded, the operator walking the next seed's walk when the launch made his walk seed
   the seed (``/vrep/operator_walk_seed`` equal to ``/vrep/seed``, as the safety benchmark's
   ``cell.launch`` does), the lock-step's counts as built; the probe's own state (columns,
   counts, clock) as at its start; ``/experiment/seed`` and ``/experiment/run_key`` the next
   walk's;
2. every other node of the launch (not ``/vrep``, ``/rosout`` nor the probe) made as launched:
   a node that offers ``~reset`` (``std_srvs/Trigger``; ``nodes/node_reset.py`` says what it
   promises) is reset in place, consumers before producers (:func:`reset_order`: what a node
   sends at its reset, a latched ready message, reaches nodes reset already, as a latched
   message reaches a node at a launch); any other is asked to shut down and started again by
   roslaunch (the launch marks it ``respawn``, after ``respawn_delay``): a new process is the
   one reset that is exactly a launch's, whatever the node keeps. A node started again must be
   gone before any comes back (else a new one could hear an old one's latched message). A
   reset refused, failed or not answered within the start time-out (a hung node), a node back
   too early, or one not back within the start time-out ends the chunk (this walk and the
   next are then not run, and the runner runs them alone);
3. the probe waits for the recorded topics' publishers as at the launch's start, and for as
   many messages on each ``wait_for`` topic as had come when the launch's first walk started
   (the nodes' ready messages), and starts the walk: without ``start_grace_s`` when every node
   was reset in place (a node started again needs it to subscribe).
"""
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
from std_srvs.srv import Trigger

from epuck_vrep_compat.compat.topics import (
    NODE, NODE_NAMESPACE, NODE_RESET_SERVICE, REWIND_SERVICE)

KEEP = {"/rosout", NODE}
POLL_S = 0.02


class ChunkError(RuntimeError):
    """The launch cannot serve the next walk (the chunk ends there)."""


def walks_of(settings):
    """[{seed, key, out}] of the probe's settings: ``~walks``, or the one run of ``~out``."""
    return settings.get("walks") or [{"seed": None, "key": None, "out": settings["out"]}]


def rewind(seed):
    """``/vrep/rewind`` to ``seed`` (the operator's walk too when the launch tied it to the
    seed); ChunkError when refused."""
    from epuck_vrep_compat.srv import Rewind
    tied = rospy.get_param(NODE_NAMESPACE + "operator_walk_seed", "") == \
        rospy.get_param(NODE_NAMESPACE + "seed", None)
    rospy.wait_for_service(REWIND_SERVICE, timeout=10.0)
    answer = rospy.ServiceProxy(REWIND_SERVICE, Rewind)(seed=int(seed),
                                                        operator_walk_seed=seed if tied else -1)
    if not answer.success:
        raise ChunkError(f"/vrep/rewind refused seed {seed}: {answer.message}")


def _alive(pid):
    """False once the process has exited (a zombie has closed its sockets already)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def renew_nodes(deadline):
    """Every node but the simulator, ``/rosout`` and the probe as launched (see the module, 2):
    reset in place, or shut down and back; the names of those started again. ChunkError when
    a reset fails or a node does not come back in time."""
    me = rospy.get_name()
    master = rosgraph.Master(me)
    state = master.getSystemState()
    nodes = [n for n in _node_names(state) if n not in KEEP and n != me]
    services = {name for name, _providers in state[2]}
    resettable = [n for n in nodes if f"{n}/{NODE_RESET_SERVICE}" in services]
    asked = time.monotonic()
    for name in reset_order(resettable, state):
        reset_node(name, deadline)
    again = [n for n in nodes if n not in resettable]
    if again:
        restart_nodes(master, again, deadline)
    rospy.loginfo("experiment_probe: reset %s; started again %s (%.2f s)",
                  ", ".join(resettable) or "none", ", ".join(again) or "none",
                  time.monotonic() - asked)
    return again


def reset_order(nodes, state):
    """``nodes`` ordered consumers first: a node after every node that subscribes to a topic it
    publishes (of ``state``, the master's ``getSystemState``); in a circle, by name."""
    subscribers = {topic: set(names) for topic, names in state[1]}
    consumers = {n: set() for n in nodes}
    for topic, publishers in state[0]:
        for p in publishers:
            if p in consumers:
                consumers[p] |= subscribers.get(topic, set()) - {p}
    order, left = [], set(nodes)
    while left:
        ready = sorted(n for n in left if not consumers[n] & left) or [min(left)]
        order += ready
        left -= set(ready)
    return order


def reset_node(name, deadline=None):
    """``<name>/reset`` called; ChunkError when it fails, is refused, or has not answered by
    ``deadline`` (``time.monotonic()``; a hung node's call is left to its daemon thread)."""
    result = {}

    def call():
        try:
            result["answer"] = rospy.ServiceProxy(f"{name}/{NODE_RESET_SERVICE}", Trigger)()
        except (rospy.ServiceException, rospy.ROSException, OSError) as e:
            result["error"] = e
    caller = threading.Thread(target=call, name=f"reset {name}", daemon=True)
    caller.start()
    caller.join(None if deadline is None else max(0.0, deadline - time.monotonic()))
    if caller.is_alive():
        raise ChunkError(f"{name}/{NODE_RESET_SERVICE} did not answer in time (a hung node)")
    if "error" in result:
        raise ChunkError(f"{name}/{NODE_RESET_SERVICE} (std_srvs/Trigger) failed: "
                         f"{result['error']}") from result["error"]
    if not result["answer"].success:
        raise ChunkError(f"{name} refused its reset: {result['answer'].message}")


def restart_nodes(master, names, deadline):
    """The nodes ``names`` shut down, gone, and back (new processes); ChunkError when one does
    not come back by ``deadline`` or comes back before every old one has gone."""
    me = rospy.get_name()
    old = {}
    for name in names:
        uri = master.lookupNode(name)
        old[name] = (uri, xmlrpc.client.ServerProxy(uri).getPid(me)[2])
    for name, (uri, _pid) in old.items():
        try:
            xmlrpc.client.ServerProxy(uri).shutdown(me, "the next walk (runs_per_launch)")
        except OSError:
            pass                            # gone already: roslaunch restarts it all the same
    while any(_alive(pid) for _uri, pid in old.values()):
        _check(deadline, "a node did not end when asked to")
    back_early = [n for n, (uri, _) in old.items() if _uri_of(master, n) not in (None, uri)]
    if back_early:
        raise ChunkError(f"{', '.join(back_early)} came back before every node had gone "
                         "(raise its respawn_delay)")
    waiting = dict(old)
    while waiting:
        waiting = {n: v for n, v in waiting.items() if _uri_of(master, n) in (None, v[0])}
        if waiting:
            _check(deadline, f"{', '.join(sorted(waiting))} did not come back (launch it with "
                   "respawn=\"true\", or give it a ~reset)")


def _node_names(state):
    return sorted({n for part in state for _topic, nodes in part for n in nodes})


def _uri_of(master, name):
    try:
        return master.lookupNode(name)
    except rosgraph.MasterError:
        return None


def _check(deadline, what):
    if time.monotonic() > deadline or rospy.is_shutdown():
        raise ChunkError(what)
    time.sleep(POLL_S)


def next_walk(probe, walk, start_timeout_s):
    """Between two walks (see the module): the launch as at its start, with ``walk``'s seed;
    the names of the nodes started again (not reset in place)."""
    deadline = time.monotonic() + start_timeout_s
    probe.times = {"probe": time.time()}
    time.sleep(probe.pace.get("settle_s", 0.0))   # the last answer reaches the simulator
    rewind(walk["seed"])
    probe.restart(walk["out"])
    rospy.set_param("/experiment/seed", walk["seed"])
    rospy.set_param("/experiment/run_key", walk["key"])
    again = renew_nodes(deadline)
    probe.reconnect(deadline)
    probe.await_ready(deadline)
    return again

"""Several runs (walks) in one launch: what the ``experiment_probe`` does between two of them.

The runner gives the probe ``~walks``, one ``{seed, out}`` per run of the chunk, the first
being the launch's own seed. After a walk's recording is written the probe makes the launch
as it was at its start, with the next seed:

1. ``/vrep/rewind`` (:mod:`epuck_vrep_compat.ros.node.rewind`): the simulation paused at time
   0, reseeded, the operator walking the next seed's walk when the launch made his walk seed
   the seed (``/vrep/operator_walk_seed`` equal to ``/vrep/seed``, as the safety benchmark's
   ``cell.launch`` does), the lock-step's counts as built;
2. every other node of the launch (not ``/vrep``, ``/rosout`` nor the probe) is asked to shut
   down and is started again by roslaunch (the launch marks it ``respawn``, after
   ``respawn_delay``): a new process is the one reset that is exactly a launch's, whatever the
   node keeps. A node must be gone before any comes back (else a new one could hear an old
   one's latched message): a node back too early, or one not back within the start time-out,
   ends the chunk (this walk and the next are then not run, and the runner runs them alone);
3. the probe's own state (columns, counts, clock) as at its start; then it waits for the
   recorded topics' publishers as at the launch's start, and starts the walk.
"""
import time
import xmlrpc.client

import rosgraph
import rospy

from epuck_vrep_compat.compat.topics import NODE, NODE_NAMESPACE, REWIND_SERVICE

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


def restart_nodes(deadline):
    """Every node but the simulator, ``/rosout`` and the probe shut down, gone, and back
    (new processes); ChunkError when one does not come back by ``deadline`` or comes back
    before every old one has gone."""
    me = rospy.get_name()
    master = rosgraph.Master(me)
    old = {}
    for name in _node_names(master):
        if name in KEEP or name == me:
            continue
        uri = master.lookupNode(name)
        old[name] = (uri, xmlrpc.client.ServerProxy(uri).getPid(me)[2])
    for name, (uri, _pid) in old.items():
        try:
            xmlrpc.client.ServerProxy(uri).shutdown(me, "the next walk (runs_per_launch)")
        except OSError:
            pass                            # gone already: roslaunch restarts it all the same
    asked = time.monotonic()
    while any(_alive(pid) for _uri, pid in old.values()):
        _check(deadline, "a node did not end when asked to")
    ended = time.monotonic()
    back_early = [n for n, (uri, _) in old.items() if _uri_of(master, n) not in (None, uri)]
    if back_early:
        raise ChunkError(f"{', '.join(back_early)} came back before every node had gone "
                         "(raise its respawn_delay)")
    waiting = dict(old)
    while waiting:
        waiting = {n: v for n, v in waiting.items() if _uri_of(master, n) in (None, v[0])}
        if waiting:
            _check(deadline, f"{', '.join(sorted(waiting))} did not come back (launch it with "
                   "respawn=\"true\")")
    rospy.loginfo("experiment_probe: %d nodes ended %.2f s after asked, back after %.2f s: %s",
                  len(old), ended - asked, time.monotonic() - asked, ", ".join(sorted(old)))


def _node_names(master):
    state = master.getSystemState()
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
    """Between two walks (see the module): the launch as at its start, with ``walk``'s seed
    (also in ``/experiment/seed`` and ``/experiment/run_key`` for the nodes started again)."""
    deadline = time.monotonic() + start_timeout_s
    probe.times = {"probe": time.time()}
    rewind(walk["seed"])
    probe.restart(walk["out"])
    rospy.set_param("/experiment/seed", walk["seed"])
    rospy.set_param("/experiment/run_key", walk["key"])
    restart_nodes(deadline)
    probe.reconnect(deadline)

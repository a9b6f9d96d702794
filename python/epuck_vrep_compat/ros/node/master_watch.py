"""What the simulator does when the ROS master goes away: it exits, loudly, with status 3.

rospy registers a node once and never again: after a master restart the node would go on
stepping and publishing to nobody (a silent zombie) while a new master knows nothing of it.
:class:`MasterWatch` asks the master once a second for its pid (taken first before the node
registered anything, so a restart during start-up counts too); when the master is another
process (it restarted and knows nothing of this node), or has not answered for ``grace_s``, it
logs a FATAL line naming the master and the process exits with status 3. Launched with
``respawn:=true``, roslaunch then starts a fresh simulator that registers with the master there
is.
"""
import os
import sys
import threading
import time

import rosgraph
import rospy

EXIT_MASTER_LOST = 3


def master_pid(caller_id: str) -> int:
    """The master's process id (call before ``rospy.init_node``, and pass it to the watch)."""
    return rosgraph.Master(caller_id).getPid()


class MasterWatch:
    """A daemon thread that exits the process when the ROS master restarts or stops answering
    (see the module's docstring)."""

    def __init__(self, first_master_pid: int, period_s: float = 1.0, grace_s: float = 3.0):
        self._master_pid = first_master_pid
        self.period_s = period_s
        self.grace_s = grace_s
        self._name = rospy.get_name()
        self._uri = rosgraph.get_master_uri()
        self._thread = threading.Thread(target=self._run, name="master_watch", daemon=True)
        self._thread.start()

    def _run(self):
        master = rosgraph.Master(self._name, master_uri=self._uri)
        unreachable_since = None
        while not rospy.is_shutdown():
            time.sleep(self.period_s)
            try:
                restarted = master.getPid() != self._master_pid
                unreachable_since = None
            except (OSError, rosgraph.MasterException):   # refused, reset, or failing
                now = time.monotonic()
                unreachable_since = unreachable_since or now
                if now - unreachable_since >= self.grace_s:
                    self._lost(f"the ROS master at {self._uri} has not answered for "
                               f"{self.grace_s:.0f} s")
                    return
                continue
            if restarted:
                self._lost(f"the ROS master at {self._uri} restarted: {self._name}'s "
                           "registrations are lost")
                return

    def _lost(self, why):
        """Log and leave at once, from this thread: rospy's clean shutdown would wait for the
        main thread, which may be retrying a registration with the vanished master forever
        (rospy sets its shutdown flag only after its pre-shutdown hooks, which take the lock
        that registration holds). There is nothing to unregister from a master that is gone."""
        rospy.logfatal("%s: exiting with status %d (relaunch, or use respawn:=true)", why,
                       EXIT_MASTER_LOST)
        for stream in (sys.stdout, sys.stderr):
            stream.flush()
        os._exit(EXIT_MASTER_LOST)

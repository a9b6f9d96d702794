"""Lock-step with a speed-and-separation supervisor (``~lockstep``): the simulator waits for the
supervisor's answer to step k before it takes step k+1, so that a safety run's outcome does
not depend on how fast the machine is (V-REP's synchronous mode, with the supervisor as the
client that triggers).

An answer is a ``/<robot>/speed_scale`` message from every watched robot (the watchdog's
robots: ``~speed_scale_robots``, every robot when empty); the simulator applies it at the next
step. Before the first step it waits for one scale from each (a supervisor in lock-step sends a
latched one when it is ready). The scale (``std_msgs/Float32``) carries no stamp, so answers
are matched to steps by number: the supervisor answers every step once, in order
(:mod:`ssm_pacing`), so once a robot has answered, its n-th later scale answers the n-th step
published after that one, however late it comes. A robot whose answer does not come within
``timeout_s`` of wall time (a dead or hung supervisor) is waited for no longer, with a warning:
the run goes on, the watchdog's protective stop in simulated time takes over, and
:attr:`late_steps` counts every step taken without waiting for some robot. Its late answers
are still counted against the steps they answer; it is waited for again only once it has
answered every step published (never, with a warning when it is lost, if it skipped one).
Scales beyond the steps published (a latched scale sent again) are ignored, with a warning:
they would otherwise release the simulator a step early from then on.
"""
import threading
import time

import rospy

POLL_S = 0.05        # wall seconds between checks of the stop request while waiting


class ScaleLockstep:
    """Matches each watched robot's speed scales to the steps they answer, and waits for them."""

    def __init__(self, robots, timeout_s: float):
        """``robots``: a callable giving the watched robots' names now. :attr:`stop_requested`
        (a callable; the node's stop request) ends a wait early."""
        self._robots = robots
        self.timeout_s = float(timeout_s)
        self.stop_requested = lambda: False
        self._cond = threading.Condition()
        self._count = {}                 # robot -> scales received so far
        self._needed = {}                # robot -> the count that answers the last step
        self._lost = set()               # robots not waited for until they catch up
        self.late_steps = 0

    def answered(self, robot: str):
        """A scale of ``robot`` arrived (the face's subscriber thread)."""
        with self._cond:
            count = self._count.get(robot, 0) + 1
            needed = self._needed.get(robot)
            if needed is not None and count > needed:
                rospy.logwarn("lockstep: a speed scale of %s answers no step (%d scales for %d "
                              "steps; a latched scale sent again?); ignored", robot, count,
                              needed)
                return
            self._count[robot] = count
            if robot in self._lost and needed is not None and count == needed:
                self._lost.discard(robot)
                rospy.loginfo("lockstep: %s has answered every step again; the simulator waits "
                              "for it", robot)
            self._cond.notify_all()

    def stepped(self):
        """A step is about to be published (under the simulation lock, before its messages
        go): from now on, one more scale from every watched robot answers it (from a robot's
        first scale on; a robot that has sent none yet is waited for to send its first)."""
        with self._cond:
            if self._lost:
                self.late_steps += 1
            for robot in self._robots():
                if robot in self._needed:
                    self._needed[robot] += 1
                elif self._count.get(robot, 0) > 0:
                    self._needed[robot] = self._count[robot] + 1

    def missing(self):
        """The watched robots (not lost) whose answer to the last step has not come, each with
        the scales received from it: [(robot, count)]."""
        with self._cond:
            return self._missing()

    def _missing(self):
        return [(r, self._count.get(r, 0)) for r in self._robots() if r not in self._lost
                and self._count.get(r, 0) < self._needed.get(r, 1)]

    def wait(self):
        """Before the next step (outside the simulation lock): until every watched robot has
        answered the last step (before the first: sent its first scale), timed out, or the
        node is asked to stop."""
        deadline = time.monotonic() + self.timeout_s
        with self._cond:
            while True:
                missing = self._missing()
                left = deadline - time.monotonic()
                if not missing or rospy.is_shutdown() or self.stop_requested():
                    return
                if left <= 0.0:
                    self._lost.update(r for r, _ in missing)
                    rospy.logwarn("lockstep: no speed scale from %s within %g s of wall "
                                  "time; stepping on without waiting for it until it has "
                                  "answered every step since (late steps so far: %d)",
                                  ", ".join(f"{r} ({n} received)" for r, n in missing),
                                  self.timeout_s, self.late_steps)
                    return
                self._cond.wait(min(left, POLL_S))

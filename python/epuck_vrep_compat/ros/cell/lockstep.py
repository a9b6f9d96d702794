"""Lock-step with a speed-and-separation supervisor (``~lockstep``): the simulator waits for the
supervisor's answer to step k before it takes step k+1, so that a safety run's outcome does
not depend on how fast the machine is (V-REP's synchronous mode, with the supervisor as the
client that triggers).

An answer is a ``/<robot>/speed_scale`` message from every watched robot (the watchdog's
robots: ``~speed_scale_robots``, every robot when empty) that arrived after the step was
published; the simulator applies it at the next step. Before the first step it waits for one
scale from each (a supervisor in lock-step sends a latched one when it is ready). A robot whose
answer does not come within ``timeout_s`` of wall time (a dead or hung supervisor) is waited for
no longer, with a warning, until it answers again: the run goes on, and the watchdog's
protective stop in simulated time takes over; :attr:`late_steps` counts those steps.
"""
import threading
import time

import rospy


class ScaleLockstep:
    """Counts each watched robot's speed scales and waits for one per step."""

    def __init__(self, robots, timeout_s: float):
        """``robots``: a callable giving the watched robots' names now."""
        self._robots = robots
        self.timeout_s = float(timeout_s)
        self._cond = threading.Condition()
        self._count = {}                 # robot -> scales received so far
        self._needed = {}                # robot -> the count that answers the last step
        self._lost = set()               # robots not waited for until they answer again
        self.late_steps = 0

    def answered(self, robot: str):
        """A scale of ``robot`` arrived (the face's subscriber thread)."""
        with self._cond:
            self._count[robot] = self._count.get(robot, 0) + 1
            if robot in self._lost:
                self._lost.discard(robot)
                rospy.loginfo("lockstep: %s answers again; the simulator waits for it", robot)
            self._cond.notify_all()

    def stepped(self):
        """A step is about to be published (under the simulation lock, before its messages
        go): from now on, the answer to it is one more scale from every watched robot."""
        with self._cond:
            for robot in self._robots():
                self._needed[robot] = self._count.get(robot, 0) + 1

    def wait(self):
        """Before the next step (outside the simulation lock): until every watched robot has
        answered the last step (before the first: sent its first scale), or timed out."""
        deadline = time.monotonic() + self.timeout_s
        with self._cond:
            while True:
                missing = [r for r in self._robots() if r not in self._lost
                           and self._count.get(r, 0) < self._needed.get(r, 1)]
                left = deadline - time.monotonic()
                if not missing or rospy.is_shutdown():
                    return
                if left <= 0.0:
                    self.late_steps += 1
                    self._lost.update(missing)
                    rospy.logwarn("lockstep: no speed scale from %s within %.1f s of wall "
                                  "time (%d received); stepping on without waiting for it "
                                  "until it answers (late steps so far: %d)",
                                  ", ".join(missing), self.timeout_s,
                                  self._count.get(missing[0], 0), self.late_steps)
                    return
                self._cond.wait(min(left, 0.5))

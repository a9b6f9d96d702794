"""Lock-step on the simulator's side, for every face: after each step the simulator waits for
one answer of that step from every watched robot (a message the robot's client sends once per
step) before it takes the next, so that a run does not depend on how fast the machine is
(V-REP's synchronous mode, with the answering client in step with the simulator).

The faces feed it: the cell's face the supervisor's ``/<robot>/speed_scale``
(:mod:`epuck_vrep_compat.ros.cell.lockstep`), the e-puck face the controllers' ``cmd_vel``
(``~lockstep_cmd_vel``); the node's loop calls :meth:`StepLockstep.stepped` under the
simulation lock before it publishes a step and :meth:`StepLockstep.wait` outside it before the
next (:class:`Locksteps`: every face's at once). A face calls :meth:`StepLockstep.answered`
once the message has taken effect (after applying it), so the next step uses it.

Answers carry no stamp, so they are matched to steps by number: the client answers every step
once, in order, so the n-th message after the baseline answers the n-th step published after
it, however late it comes. The baseline: with ``handshake`` (a supervisor that sends a latched
answer when it is ready), the simulator waits before the first step for one message from each
robot and counts from a robot's first message on; without it (a controller that answers the
sensor messages of each step, so nothing before the first), it does not wait before the first
step, and what came before the first step answers no step. A robot whose answer does not come
within ``timeout_s`` of wall time (a hung client), or whose client answered and has since
disconnected (a dead one: not waited for at all), is waited for no longer, with a warning:
the run goes on and :attr:`late_steps` counts every step taken without waiting for some
robot. Its late answers are still counted against the steps they answer; it is waited
for again only once it has answered every step published (never, with a warning when it is
lost, if it skipped one). Messages beyond the steps published: by default (a supervisor's
latched answer, sent again on a reconnection) ignored, with a warning, since they would
otherwise release the simulator a step early from then on; with ``early_answers`` (a
controller's command, never latched) they answer the next steps, as the experiment probe
counts them (a node on a timer that fired twice in one step has answered the next one).
"""
import threading
import time

import rospy

from epuck_vrep_compat.ros.common.late_steps import LateSteps

POLL_S = 0.05        # wall seconds between checks of the stop request while waiting


class StepLockstep:
    """Matches each watched robot's answers to the steps they answer, and waits for them."""

    def __init__(self, robots, timeout_s: float, what: str, handshake: bool = True,
                 early_answers: bool = False, connected=None):
        """``robots``: a callable giving the watched robots' names now; ``what``: the answer's
        name in the log (``speed scale``, ``cmd_vel``); ``handshake``: wait before the first
        step for one answer from each; ``early_answers``: an answer beyond the steps published
        answers the next step (see the module); ``connected``: a callable, whether a robot's
        client is still connected (default: always): one that answered and is no longer
        connected is not waited for, and a step taken without waiting for a connected one is
        counted for the experiment (``late_steps.py``).
        :attr:`stop_requested` (a callable; the node's stop request) ends a wait early."""
        self._robots = robots
        self.timeout_s = float(timeout_s)
        self.what = what
        self._first_needed = 1 if handshake else 0
        self._early_answers = early_answers
        self.stop_requested = lambda: False
        self._cond = threading.Condition()
        self._count = {}                 # robot -> answers received so far
        self._needed = {}                # robot -> the count that answers the last step
        self._lost = set()               # robots not waited for until they catch up
        self.late_steps = 0
        # a step taken without waiting for a robot whose client is still connected (a hung or
        # slow one: the step's outcome then depends on the machine) goes to the experiment
        self._connected = connected or (lambda _robot: True)
        self.late = LateSteps()

    def restart(self):
        """As built: no answer received, none needed, nobody lost (a rewind)."""
        with self._cond:
            self._count, self._needed, self._lost = {}, {}, set()
            self.late_steps = 0

    def settle(self):
        """Until every watched robot (not lost) has answered every step published, at most
        ``timeout_s`` of wall time, with a warning then (before a rewind: an answer to the last
        step still on its way would otherwise count against the next run's first step)."""
        deadline = time.monotonic() + self.timeout_s
        with self._cond:
            while not rospy.is_shutdown() and not self.stop_requested():
                owed = sorted(r for r, n in self._needed.items()
                              if r not in self._lost and self._count.get(r, 0) < n)
                left = deadline - time.monotonic()
                if not owed:
                    return
                if left <= 0.0:
                    rospy.logwarn("lockstep: the last step's %s of %s did not come within %g s",
                                  self.what, ", ".join(owed), self.timeout_s)
                    return
                self._cond.wait(min(left, POLL_S))

    def answered(self, robot: str):
        """An answer of ``robot`` arrived and took effect (the face's subscriber thread)."""
        with self._cond:
            count = self._count.get(robot, 0) + 1
            needed = self._needed.get(robot)
            if needed is not None and count > needed and not self._early_answers:
                rospy.logwarn("lockstep: a %s of %s answers no step (%d for %d steps; a "
                              "latched one sent again?); ignored", self.what, robot, count,
                              needed)
                return
            self._count[robot] = count
            if robot in self._lost and needed is not None and count >= needed:
                self._lost.discard(robot)
                rospy.loginfo("lockstep: %s has answered every step again; the simulator waits "
                              "for it", robot)
            self._cond.notify_all()

    def stepped(self):
        """A step is about to be published (under the simulation lock, before its messages
        go): from now on, one more answer from every watched robot answers it (with a
        handshake, from a robot's first answer on: one that has sent none yet is waited for
        to send its first)."""
        with self._cond:
            if self._lost:
                self.late_steps += 1
                if any(self._connected(r) for r in self._lost):
                    self.late.add()
            for robot in self._robots():
                count = self._count.get(robot, 0)
                if robot in self._needed:
                    self._needed[robot] += 1
                elif count > 0 or not self._first_needed:
                    self._needed[robot] = count + 1

    def missing(self):
        """The watched robots (not lost) whose answer to the last step has not come, each with
        the answers received from it: [(robot, count)]."""
        with self._cond:
            return self._missing()

    def _missing(self):
        return [(r, self._count.get(r, 0)) for r in self._robots() if r not in self._lost
                and self._count.get(r, 0) < self._needed.get(r, self._first_needed)]

    def wait(self):
        """Before the next step (outside the simulation lock): until every watched robot has
        answered the last step (with a handshake, before the first: sent its first answer),
        timed out, or the node is asked to stop."""
        deadline = time.monotonic() + self.timeout_s
        with self._cond:
            while True:
                missing = self._missing()
                left = deadline - time.monotonic()
                if not missing or rospy.is_shutdown() or self.stop_requested():
                    return
                gone = [r for r, n in missing if n > 0 and not self._connected(r)]
                if gone:
                    # a client that answered and whose connection has closed is dead: its
                    # answer will not come, so the timeout (meant for a hung one) is not waited
                    self._lost.update(gone)
                    rospy.logwarn("lockstep: the %s client of %s has disconnected; stepping on "
                                  "without waiting for it until it has answered every step "
                                  "since", self.what, ", ".join(gone))
                    continue
                if left <= 0.0:
                    self._lost.update(r for r, _ in missing)
                    rospy.logwarn("lockstep: no %s from %s within %g s of wall time; stepping "
                                  "on without waiting for it until it has answered every step "
                                  "since (late steps so far: %d)", self.what,
                                  ", ".join(f"{r} ({n} received)" for r, n in missing),
                                  self.timeout_s, self.late_steps)
                    return
                self._cond.wait(min(left, POLL_S))


class Locksteps:
    """Every face's lock-step, called as one by the node (:meth:`of`: None when no face has
    one, so that the node's free-running path stays as it was)."""

    def __init__(self, locksteps):
        self._all = list(locksteps)

    @classmethod
    def of(cls, locksteps):
        present = [ls for ls in locksteps if ls is not None]
        return cls(present) if present else None

    @property
    def stop_requested(self):
        return self._all[0].stop_requested

    @stop_requested.setter
    def stop_requested(self, callable_):
        for ls in self._all:
            ls.stop_requested = callable_

    def stepped(self):
        for ls in self._all:
            ls.stepped()

    def restart(self):
        for ls in self._all:
            ls.restart()

    def settle(self):
        for ls in self._all:
            ls.settle()

    def wait(self):
        for ls in self._all:
            ls.wait()

"""When the simulation steps: running, paused or stopped, free or synchronous (V-REP's model).

* ``running``: the node's loop steps at the real-time factor; in synchronous mode it waits for a
  trigger before each step (exactly one step per trigger).
* ``paused``: time stands still; the ``step`` service may still advance it by hand.
* ``stopped``: like V-REP after simStopSimulation: the scene is back at its start, the frame id
  of ``/vrep/info`` reads -1 until the next start. ``/clock`` keeps increasing across a
  stop/start so TF buffers never see time go backwards; ``/vrep/info`` reports the time since
  the last start, as V-REP does.
"""
import threading

RUNNING, PAUSED, STOPPED = "running", "paused", "stopped"


class SimulationControl:
    """The simulation's run state (running, paused, stopped; free or synchronous), as V-REP's
    start, pause, stop and trigger calls change it."""

    def __init__(self, sim, initial_state: str = RUNNING):
        self._sim = sim
        self._lock = threading.Condition()      # notified whenever the loop may step
        self.state = initial_state
        self.synchronous = False
        self._triggers = 0
        self._start_frame = sim.frame if initial_state != STOPPED else None
        self.listeners = []           # called with the new state on start, stop

    # --- what the loop asks ------------------------------------------------------------------
    def may_step(self) -> bool:
        """True when the loop should take one step now (consumes a trigger in sync mode)."""
        with self._lock:
            if self.state != RUNNING:
                return False
            if not self.synchronous:
                return True
            if self._triggers > 0:
                self._triggers -= 1
                return True
            return False

    def wait_until_may_step(self, timeout_s: float):
        """Until the loop may step (a start, a trigger, free running) or ``timeout_s`` of wall
        time passed: the idle loop's wait, which a trigger ends at once (no polling)."""
        with self._lock:
            if not self._may_step_locked():
                self._lock.wait(timeout_s)

    def _may_step_locked(self) -> bool:
        return self.state == RUNNING and (not self.synchronous or self._triggers > 0)

    @property
    def waiting_for_trigger(self) -> bool:
        return self.state == RUNNING and self.synchronous and self._triggers == 0

    # --- V-REP's simulation calls -----------------------------------------------------------
    def start(self) -> int:
        """1 when started or resumed, 0 when already running (V-REP's results)."""
        with self._lock:
            if self.state == RUNNING:
                return 0
            was_stopped = self.state == STOPPED
            self.state = RUNNING
            if was_stopped:
                self._start_frame = self._sim.frame
            self._lock.notify_all()
        if was_stopped:
            self._notify(RUNNING)
        return 1

    def pause(self) -> int:
        with self._lock:
            if self.state != RUNNING:
                return 0
            self.state = PAUSED
        return 1

    def stop(self) -> int:
        """Back to the start state; streams end (listeners are told)."""
        with self._lock:
            if self.state == STOPPED:
                return 0
            self.state = STOPPED
            self._start_frame = None
            self.synchronous_triggers_reset()
        self._notify(STOPPED)
        return 1

    def rewind(self):
        """Paused at frame 0, free-running, no trigger pending: as built paused (a rewind)."""
        with self._lock:
            self.state = PAUSED
            self.synchronous = False
            self._triggers = 0
            self._start_frame = 0

    def synchronous_triggers_reset(self):
        self._triggers = 0

    def set_synchronous(self, enable: bool) -> int:
        with self._lock:
            self.synchronous = bool(enable)
            self._triggers = 0
            self._lock.notify_all()
        return 1

    def trigger(self) -> int:
        """Release exactly one step; -1 when not in synchronous mode."""
        with self._lock:
            if not self.synchronous:
                return -1
            self._triggers += 1
            self._lock.notify_all()
        return 1

    # --- what /vrep/info reports ----------------------------------------------------------
    @property
    def frame_id(self) -> int:
        """Steps since the last start; -1 while stopped (V-REP's simulation frame id)."""
        start = self._start_frame
        return -1 if start is None else self._sim.frame - start

    @property
    def time_since_start_s(self) -> float:
        return max(0, self.frame_id) * self._sim.step_s

    def _notify(self, state):
        for listener in list(self.listeners):
            listener(state)

"""A test-only extension that fails on command, so that the simulator's fault paths run.

Never part of a scene: the builder adds it only when its config asks (``fault_hook``; the
node's ``~test_fault_hook`` parameter, false by default), after every other extension, and the
node then offers its commands as services (``ros/node/fault_face.py``). Three faults:

* :meth:`FaultHook.raise_in_next_step`: the next step raises :class:`InjectedFault`, once (the
  node pauses the simulation and logs an ERROR line naming the error);
* :meth:`FaultHook.block_next_step`: the next step sleeps that many seconds of wall time, once
  (the node falls behind its real-time schedule and says so);
* :meth:`FaultHook.set_publish_fault`: while on, :meth:`FaultHook.check_publish`, which the
  fault hook's face calls in its ``publish``, raises :class:`InjectedFault` (the node logs it,
  throttled, and the other faces publish on).

A reset (and a stop) disarms the step faults not yet fired and the publish fault.
"""
import threading
import time

from epuck_vrep_compat.sim.extension import SimulationExtension


class InjectedFault(RuntimeError):
    """The error the fault hook raises; its message says where it was injected."""


class FaultHook(SimulationExtension):
    """Faults on command (see the module's docstring); claims no object."""

    def __init__(self):
        self._lock = threading.Lock()
        self._raise_next = False
        self._block_next_s = 0.0
        self._publish_fault = False

    def raise_in_next_step(self):
        with self._lock:
            self._raise_next = True

    def block_next_step(self, seconds: float):
        if not seconds > 0.0:
            raise ValueError(f"a step blocks for a positive time, not {seconds} s")
        with self._lock:
            self._block_next_s = float(seconds)

    def set_publish_fault(self, on: bool):
        with self._lock:
            self._publish_fault = bool(on)

    @property
    def publish_fault(self) -> bool:
        return self._publish_fault

    def check_publish(self):
        """Raises :class:`InjectedFault` while the publish fault is on."""
        if self._publish_fault:
            raise InjectedFault("injected fault in a face's publish (test fault hook)")

    def step(self, dt: float) -> None:
        with self._lock:
            raise_now, block_s = self._raise_next, self._block_next_s
            self._raise_next, self._block_next_s = False, 0.0
        if block_s > 0.0:
            time.sleep(block_s)
        if raise_now:
            raise InjectedFault("injected fault in a simulation step (test fault hook)")

    def reset(self) -> None:
        with self._lock:
            self._raise_next, self._block_next_s, self._publish_fault = False, 0.0, False

"""The ``/vrep`` face: V-REP's legacy ROS plugin (vrep_common) on our simulation.

``/vrep/info`` goes out once per simulation step (and every ``IDLE_INFO_PERIOD_S`` of wall time
while paused, stopped or waiting for a synchronous trigger, as on the plugin's GUI passes); the
``simRos*`` services and the enabled streams are in :mod:`services` and
:mod:`streams`. The simulator node must be named ``vrep`` so that everything lands under
``/vrep/`` as clients expect.
"""
import time

from std_msgs.msg import Float32, Int32
from vrep_common.msg import VrepInfo

from epuck_vrep_compat.compat.topics import INFO_TOPIC
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher
from epuck_vrep_compat.ros.vrep_plugin.services import VrepServices
from epuck_vrep_compat.ros.vrep_plugin.streams import VrepStreams
from epuck_vrep_compat.sim.control import STOPPED

IDLE_INFO_PERIOD_S = 0.05


class VrepFace(Face):
    """V-REP's legacy plugin: ``/vrep/info``, the ``simRos*`` services and the enabled streams."""

    def __init__(self, backend, lock):
        self.backend = backend
        self._info = synchronous_publisher(INFO_TOPIC, VrepInfo)
        self.streams = VrepStreams(backend, lock)
        self.services = VrepServices(backend, lock, self.streams)
        self._last_idle_info = 0.0
        backend.control.listeners.append(self._on_state)

    def _on_state(self, state):
        if state == STOPPED:
            self.streams.remove_all()

    def info_message(self, stamp) -> VrepInfo:
        frame_id, state, sim_time, step = self.backend.info()
        msg = VrepInfo()
        msg.headerInfo.seq = frame_id & 0xFFFFFFFF      # -1 before a start, as V-REP's uint32
        msg.headerInfo.stamp = stamp
        msg.simulatorState = Int32(state)
        msg.simulationTime = Float32(sim_time)
        msg.timeStep = Float32(step)
        return msg

    def publish(self, step: Step):
        """After a step: info (when someone listens), then every enabled stream (one way:
        state -> ROS)."""
        if step.batch.wanted(self._info):
            step.batch.add(self._info, self.info_message(step.stamp))
        self.streams.publish(step.batch, step.secs, step.nsecs)

    def publish_idle(self, step: Step):
        """While not stepping (paused, stopped, waiting for a trigger): info and the enabled
        streams every ``IDLE_INFO_PERIOD_S``, as the plugin did on V-REP's GUI passes."""
        now = time.monotonic()
        if now - self._last_idle_info >= IDLE_INFO_PERIOD_S:
            self._last_idle_info = now
            step.batch.add(self._info, self.info_message(step.stamp))
            self.streams.publish(step.batch, step.secs, step.nsecs)

"""The ``/vrep`` face: V-REP's legacy ROS plugin (vrep_common) on our simulation.

``/vrep/info`` goes out once per simulation step (and every ``IDLE_INFO_PERIOD_S`` of wall time
while paused, stopped or waiting for a synchronous trigger, as on the plugin's GUI passes); the
``simRos*`` services and the enabled streams are in :mod:`services` and
:mod:`streams`. The simulator node must be named ``vrep`` so that everything lands under
``/vrep/`` as clients expect.

What the scene's scripts publish from the start (the model's
:meth:`~epuck_vrep_compat.sim.simulation.Simulation.published_signals`: the cell's blob
signals, ``/vrep/Blob_Camera_0_X`` ...) is enabled here, as those scripts called
simRosEnablePublisher in their first pass: before the first step's streams go out after each
start; every stream ends at a stop, so the next start enables them again.
"""
import time

from std_msgs.msg import Float32, Int32
from vrep_common.msg import VrepInfo
from vrep_common.srv import simRosEnablePublisherRequest

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.topics import INFO_TOPIC
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher
from epuck_vrep_compat.ros.vrep_plugin.services import VrepServices
from epuck_vrep_compat.ros.vrep_plugin.streams import VrepStreams
from epuck_vrep_compat.sim.control import STOPPED

IDLE_INFO_PERIOD_S = 0.05
SIGNAL_STREAM_COMMANDS = {"int": vc.STRMCMD_GET_INTEGER_SIGNAL,
                          "float": vc.STRMCMD_GET_FLOAT_SIGNAL,
                          "string": vc.STRMCMD_GET_STRING_SIGNAL}


class VrepFace(Face):
    """V-REP's legacy plugin: ``/vrep/info``, the ``simRos*`` services and the enabled streams."""

    def __init__(self, backend):
        """Services and subscriber streams act on the model under its lock (``sim.lock``)."""
        self.backend = backend
        self._info = synchronous_publisher(INFO_TOPIC, VrepInfo)
        self.streams = VrepStreams(backend, backend.sim.lock)
        self.services = VrepServices(backend, backend.sim.lock, self.streams)
        self._last_idle_info = 0.0
        self._scripts_started = False     # the scripts' signal streams enabled since the start
        backend.control.listeners.append(self._on_state)

    def _on_state(self, state):
        if state == STOPPED:
            self.streams.remove_all()
            self._scripts_started = False

    def _start_scripts(self):
        """The scripts' first pass: enable the publishers of the signals they publish."""
        for kind, name in self.backend.sim.published_signals():
            self.streams.enable_publisher(simRosEnablePublisherRequest(
                topicName=name, queueSize=1, streamCmd=SIGNAL_STREAM_COMMANDS[kind],
                auxInt1=-1, auxInt2=-1, auxString=name))
        self._scripts_started = True

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
        """After a step: the scripts' streams enabled once running, info (when someone
        listens), then every enabled stream (one way: state -> ROS)."""
        if not self._scripts_started and self.backend.running:
            self._start_scripts()
        if step.batch.wanted(self._info):
            step.batch.add(self._info, self.info_message(step.stamp))
        self._publish_streams(step)

    def _publish_streams(self, step: Step):
        self.streams.publish(step.batch, step.secs, step.nsecs,
                             send_transforms=lambda msg: step.add_tf("streams", msg))

    def publish_idle(self, step: Step):
        """While not stepping (paused, stopped, waiting for a trigger): info and the enabled
        streams every ``IDLE_INFO_PERIOD_S``, as the plugin did on V-REP's GUI passes."""
        now = time.monotonic()
        if now - self._last_idle_info >= IDLE_INFO_PERIOD_S:
            self._last_idle_info = now
            step.batch.add(self._info, self.info_message(step.stamp))
            self._publish_streams(step)

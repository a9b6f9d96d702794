"""The cell's face: what V-REP's cell scene published through its models' scripts.

- The laser scan (:mod:`laser`), the cell's TF (:mod:`transforms`), each robot's joint topics
  (:mod:`joints`) and what rviz needs (:mod:`rviz`).
- The safety interface (:mod:`safety`): each robot's speed scale in, the operator-to-link
  separation service.
- The ceiling cameras' blob positions, exactly as the thesis's child script did it: each step
  the cell writes the camera's blob x and y as float signals (``Cell._write_blob_signals``), and
  publishers of those signals (``simros_strmcmd_get_float_signal``) are enabled here, through
  the plugin's stream machinery, when the simulation starts: ``/vrep/Blob_Camera_0_X`` ... They
  publish only while the operator is in view (V-REP's blob filter returns no blob otherwise).
"""
from vrep_common.srv import simRosEnablePublisherRequest

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.ros.cell.joints import ArmTopics
from epuck_vrep_compat.ros.cell.laser import LaserTopic
from epuck_vrep_compat.ros.cell.rviz import CellRviz
from epuck_vrep_compat.ros.cell.safety import CellSafety
from epuck_vrep_compat.ros.cell.transforms import CellTransforms
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.sim.control import STOPPED


class CellFace(Face):
    """The industrial cell: joint states and commands, the laser scan, the cell's TF, the blob
    signal streams, robot descriptions and markers for rviz.

    ``streams``: the ``/vrep`` plugin's :class:`VrepStreams`, where the blob streams are
    enabled (as the thesis's script called simRosEnablePublisher); ``lock``: the simulation
    lock commands take; ``static_tf``: the node's ``/tf_static``."""

    def __init__(self, sim, streams, lock, static_tf):
        self.sim = sim
        self.cell = sim.cell
        self._streams = streams
        self._backend = streams.backend
        self._blob_enabled = False
        self._backend.control.listeners.append(self._on_state)
        self._laser = LaserTopic(self.cell) if self.cell.laser is not None else None
        self._lock, self._log = lock, ThrottledLog()
        log = self._log
        self._safety = CellSafety(sim, lock, log)
        self._arms = {arm.spec.name: ArmTopics(arm, lock, log) for arm in self.cell.arms}
        self._transforms = CellTransforms(sim, static_tf)
        self._rviz = CellRviz(sim, static_tf)

    def sync(self):
        """Follow the cell's objects after a removal or a robot loaded (between steps, under
        the lock): the removed robots' topics and descriptions, the laser's topic and the
        removed objects' TF frames go, a loaded robot's come; the markers are re-sent."""
        for name in [n for n in self._arms if n not in self.cell.arm_by_name]:
            self._arms.pop(name).close()
            self._rviz.forget_robot(name)
        for arm in [a for a in self.cell.arms if a.spec.name not in self._arms]:
            self._arms[arm.spec.name] = ArmTopics(arm, self._lock, self._log)
            self._rviz.describe(arm)
        self._safety.sync()
        if self._laser is not None and self.cell.laser is None:
            self._laser.close()
            self._laser = None
        self._transforms.index()
        self._rviz.publish_markers()

    def _on_state(self, state):
        if state == STOPPED:
            self._blob_enabled = False       # V-REP removes every stream at the end

    def _enable_blob_streams(self):
        """The thesis's child script, first pass: enable the float-signal publishers."""
        for camera in self.cell.camera_specs:
            for topic in camera.blob_topics:
                req = simRosEnablePublisherRequest(topicName=topic, queueSize=1,
                                                   streamCmd=vc.STRMCMD_GET_FLOAT_SIGNAL,
                                                   auxInt1=-1, auxInt2=-1, auxString=topic)
                self._streams.enable_publisher(req)
        self._blob_enabled = True

    def publish(self, step: Step):
        """The blob streams enabled once running (before ``/vrep``'s streams publish), TF, the
        laser scan when the cell took one, the joint states."""
        if not self._blob_enabled and self._backend.running:
            self._enable_blob_streams()
        batch, stamp = step.batch, step.stamp
        self._transforms.update_static(step.secs, step.nsecs)
        if batch.wanted(step.tf):
            batch.add(step.tf, self._transforms.message(step.secs, step.nsecs))
        if self._laser is not None:
            self._laser.publish(batch, stamp)
        for arm in self._arms.values():
            arm.publish(batch, stamp)

"""The simulator node ``/vrep``: parameters in, one simulation, its ROS faces, ``/clock``.

Faces: the e-puck topic profile (``EpuckFace``, ``TfFace``, ``CameraFace``, ``LedFace``) and
V-REP's legacy plugin (``VrepFace``: ``/vrep/info``, ``/vrep/simRos*``, enabled streams). Our own
services: ``~step`` (``epuck_vrep_compat/StepSimulation``: N steps while paused; in lock-step with
a supervisor each after its answer to the last, as the loop's), ``~pause``, ``~unpause`` and
``~reset`` (``std_srvs/Empty``), ``~rewind`` (:mod:`.rewind`).

Every face has the shape of :class:`~epuck_vrep_compat.ros.face.Face`; the node keeps them in one
list and after each step calls ``publish(step)`` on each (on idle passes ``publish_idle(step)``).
What a topic gets does not depend on the list's order: the node sends ``/clock`` first and the
step's ``/tf`` parts last, in their own order (``Step.send_tf``). Robots loaded, pasted or removed
through ``/vrep`` change the simulation under its lock (``sim.lock``, which every step holds),
between steps; the simulation then calls :meth:`SimulatorNode._on_robots_changed`, and every face
follows (``sync()``) before the next step.
"""
import contextlib
import time
import traceback

import rospy
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty, EmptyResponse
from tf2_msgs.msg import TFMessage

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.compat.topics import (
    CLOCK_TOPIC, PAUSE_SERVICE, RESET_SERVICE, TF_TOPIC, UNPAUSE_SERVICE)
from epuck_vrep_compat.ros.common.lockstep import Locksteps
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.epuck.camera import CameraFace
from epuck_vrep_compat.ros.epuck.description import DescriptionFace
from epuck_vrep_compat.ros.epuck.drivers.extras import ExtrasFace
from epuck_vrep_compat.ros.epuck.leds import LedFace
from epuck_vrep_compat.ros.epuck.profiles import PROFILES
from epuck_vrep_compat.ros.epuck.sensors import EpuckFace
from epuck_vrep_compat.ros.epuck.transforms import TfFace
from epuck_vrep_compat.ros.face import Step
from epuck_vrep_compat.ros.messages import time_stamp
from epuck_vrep_compat.ros.node.params import ParamError, SimParams, with_operator
from epuck_vrep_compat.ros.node.rewind import RewindService
from epuck_vrep_compat.ros.transport.static_tf import StaticTransforms
from epuck_vrep_compat.ros.transport.step_batch import StepBatch, synchronous_publisher
from epuck_vrep_compat.ros.vrep_plugin.face import VrepFace
from epuck_vrep_compat.scene.model_files import ModelLibrary
from epuck_vrep_compat.scene.scene_file import SceneError, load_scene
from epuck_vrep_compat.sim.control import PAUSED, RUNNING, STOPPED, SimulationControl
from epuck_vrep_compat.srv import StepSimulation, StepSimulationResponse
from epuck_vrep_compat.vrep.backend import VrepBackend

MAX_STEPS_PER_CALL = 100000
_LAG_RESET_S = 0.5       # behind schedule by more than this: stop trying to catch up
_IDLE_SLEEP_S = 0.01     # idle pass period while paused, stopped or waiting for a trigger
                         # (a start or a trigger ends the wait at once)


class SimulatorNode:
    """The simulator node: one simulation, stepped at the requested rate, and its faces."""

    def __init__(self, params: SimParams, models_dir: str = None):
        """``models_dir``: the package's folder of the model files simRosLoadModel loads
        (``params.model_dirs``, the user's, come after it)."""
        self.params = params
        scene = with_operator(load_scene(params.world), params)
        profile = PROFILES[params.profile]
        names = params.robot_names
        config = SimulationConfig(names, params.step_s, params.seed, params.noise,
                                  params.cmd_timeout_s, params.camera, profile.robot_name,
                                  params.extras if profile.extras else None, profile.extras,
                                  fault_hook=params.test_fault_hook)
        try:
            self.sim = build_simulation(scene, config)
        except SceneError as e:
            raise ParamError(f"parameter '~n' ({params.n}) with scene '{params.world}': {e}")
        self._lock = self.sim.lock          # the model's: stepping, services and commands
        self._errors = ThrottledLog()
        self._batch = StepBatch(background=True)    # sends while the next step is prepared
        self.control = SimulationControl(self.sim, PAUSED if params.paused else RUNNING)
        self.control.listeners.append(self._on_state)
        self._clock = synchronous_publisher(CLOCK_TOPIC, Clock)
        self._tf_pub = synchronous_publisher(TF_TOPIC, TFMessage)
        self._tf_static = StaticTransforms()
        self.leds = LedFace(profile, self.sim, self._batch)
        self.epucks = EpuckFace(profile, self.sim, params.cmd_vel_scaling, params.accel_sign,
                                params.publish_ground_truth, params.cmd_vel_lockstep)
        self.tf = TfFace(profile, self.sim, self._tf_static)
        self.cameras = CameraFace(profile, self.sim, params.camera_mode)
        self.extras = None
        if self.sim.epuck2 is not None:      # the drivers' extra sensors, after the swarm's
            self.extras = ExtrasFace(profile, self.sim, self.sim.epuck2, params.accel_sign)
        models = ModelLibrary(models_dir, params.model_dirs) if models_dir else None
        self.vrep = VrepFace(VrepBackend(self.sim, self.control, params.vrep_realtime, models))
        self.sim.listeners.append(self._on_robots_changed)
        self.cell = None
        if self.sim.cell is not None:
            from epuck_vrep_compat.ros.cell.face import CellFace
            watchdog = (params.speed_scale_timeout_s, params.speed_scale_robots or None)
            try:
                self.cell = CellFace(self.sim, self._tf_static, watchdog,
                                     params.lockstep_timeout_s)
            except ValueError as e:
                raise ParamError(f"parameter '~speed_scale_robots': {e}") from None
            if self.sim.cell.operator is not None:
                rospy.loginfo("operator: %s", self.sim.cell.operator.describe())
        self._lockstep = Locksteps.of([getattr(self.cell, "lockstep", None),
                                       self.epucks.lockstep])     # None: free-running
        self.descriptions = DescriptionFace(profile, self.sim)
        faults = None
        if self.sim.fault_hook is not None:      # tests only; first, so the others follow it
            from epuck_vrep_compat.ros.node.fault_face import FaultFace
            faults = FaultFace(self.sim.fault_hook)
        self.faces = [f for f in (faults, self.tf, self.epucks, self.extras, self.cell,
                                  self.vrep, self.cameras, self.leds, self.descriptions)
                      if f is not None]
        self._advertise()
        self.leds.publish(self._step_info())

    def _advertise(self):
        """Our own services (see the module's docstring)."""
        rospy.Service("~step", StepSimulation, self._on_step)
        rospy.Service(PAUSE_SERVICE, Empty, self._on_pause)
        rospy.Service(UNPAUSE_SERVICE, Empty, self._on_unpause)
        rospy.Service(RESET_SERVICE, Empty, self._on_reset)
        self._rewind = RewindService(self.sim, self.control, self._lockstep, self.cell)

    @property
    def batch(self):
        """The ``StepBatch`` every face queues its messages in (the stop drains it)."""
        return self._batch

    # --- services ------------------------------------------------------------------------
    def _on_step(self, req):
        if self.control.state != PAUSED:
            return StepSimulationResponse(False, f"the simulation is {self.control.state}; "
                                          "pause it first", self.sim.frame, self.sim.time_s)
        if req.steps > MAX_STEPS_PER_CALL:
            return StepSimulationResponse(False, f"at most {MAX_STEPS_PER_CALL} steps per call",
                                          self.sim.frame, self.sim.time_s)
        failure = None
        # the steps are one piece under the lock, except in lock-step: the supervisor's answer
        # to each step takes the lock, so the call lets go of it while it waits for the answer
        with self._lock if self._lockstep is None else contextlib.nullcontext():
            for _ in range(req.steps):
                failure = self._step_by_hand()
                if failure:
                    break
            with self._lock:
                self._batch.flush()
                self._batch.settle()     # the steps' messages are on their way before the answer
        return StepSimulationResponse(not failure, failure or "", self.sim.frame,
                                      self.sim.time_s)

    def _step_by_hand(self):
        """One step of a ``~step`` call; in lock-step after the supervisor's answer to the last
        one, and sent at once (the supervisor answers it). None, or why it failed."""
        if self._lockstep is not None:
            self._lockstep.wait()
        with self._lock:
            if self.control.state != PAUSED:      # started meanwhile: the loop steps now
                return f"the simulation was {self.control.state} while stepping"
            if self._lockstep is not None:
                self._lockstep.stepped()
            if not self._step_and_publish():
                return "the simulation step failed (see the node's log)"
            if self._lockstep is not None or self._batch.due():
                self._batch.flush()
        return None

    def _on_pause(self, _req):
        self.control.pause()
        rospy.loginfo("simulation paused at t=%.3f s", self.sim.time_s)
        return EmptyResponse()

    def _on_unpause(self, _req):
        self.control.start()
        rospy.loginfo("simulation running from t=%.3f s", self.sim.time_s)
        return EmptyResponse()

    def _on_reset(self, _req):
        with self._lock:
            self.sim.reset()
        rospy.loginfo("simulation reset: robots at their start poses (time keeps running)")
        return EmptyResponse()

    def _on_state(self, state):
        if state == STOPPED:
            with self._lock:
                self.sim.reset()
            rospy.loginfo("simulation stopped: the scene is back at its start")
        elif state == RUNNING:
            rospy.loginfo("simulation started")

    def _on_robots_changed(self):
        """Robots or objects came or went (a /vrep service, under the lock): every face
        follows now, so the next step publishes for exactly the robots there are."""
        with self._lock:
            for face in self.faces:
                face.sync()
        robots = list(self.sim.epucks.robot_names)
        if self.sim.cell is not None:
            robots += [arm.spec.name for arm in self.sim.cell.arms]
        rospy.loginfo("scene changed: %d robot(s): %s", len(robots), ", ".join(robots) or "none")

    # --- the loop ------------------------------------------------------------------------
    def _step_info(self) -> Step:
        """What the faces publish a step with: the simulation time, the batch, ``/tf``."""
        stamp = time_stamp(self.sim.time_s)
        return Step(stamp.secs, stamp.nsecs, self._batch, self._tf_pub)

    def _step_and_publish(self) -> bool:
        """One step and its messages; False when the step failed (see :meth:`_step_failed`)."""
        try:
            self.sim.step()
        except Exception as e:  # noqa: BLE001 - the simulation must outlive it, and says so
            self._step_failed(e)
            return False
        step = self._step_info()
        if self._batch.wanted(self._clock):
            self._batch.add(self._clock, Clock(clock=step.stamp))
        self._publish_faces(step, idle=False)
        step.send_tf()
        return True

    def _publish_faces(self, step: Step, idle: bool):
        """Every face's messages of a step (or idle pass); a face that raises loses only its own
        messages of this pass, with an ERROR line (one per face and 5 s), and the others publish
        on."""
        for face in self.faces:
            try:
                face.publish_idle(step) if idle else face.publish(step)
            except Exception as e:  # noqa: BLE001 - one face's bug must not silence the others
                name = type(face).__name__
                self._errors.error(f"publish {name}", "%s failed to publish at t=%.3f s (%s: %s);"
                                   " the other faces publish on:\n%s", name, self.sim.time_s,
                                   type(e).__name__, e, traceback.format_exc())

    def _step_failed(self, error: Exception):
        """Physics refused to step (every request is checked before it reaches the scene, so
        this is a bug): the simulation pauses, so that /vrep/info says "paused" rather than
        "running" while time stands still, and the error is logged with its cause, every time
        (each one pauses, so they cannot flood). Stop, start and reset still work; starting
        again retries the step."""
        self.control.pause()
        rospy.logerr("simulation step failed at t=%.3f s (%s: %s); the simulation is paused "
                     "(start, stop or reset it through /vrep):\n%s", self.sim.time_s,
                     type(error).__name__, error, traceback.format_exc())

    def _guarded(self, work):
        """A bug in one face must not stop the simulation: log it loudly and go on."""
        try:
            work()
        except Exception:  # noqa: BLE001 - the loop outlives any one failure, which is logged
            self._errors.error("publish", "publishing a step failed:\n%s",
                               traceback.format_exc())

    def spin(self, stop_requested=lambda: False):
        """Step at ``rtf`` times real time (or as fast as possible at 0) while running, until
        ``stop_requested()`` (checked after every step) or rospy shuts down. Messages are
        flushed before every sleep, so a simulation that keeps its schedule delivers every step
        at once; one that runs flat out flushes every ``max_delay_s``. A step late by up to
        ``_LAG_RESET_S`` is caught up (the next steps do not sleep); one later than that
        restarts the schedule: the time is dropped, with a warning. A pause or stop answered
        while the loop waited to step wins: no step follows its answer."""
        period_s = self.params.step_s / self.params.rtf if self.params.rtf > 0 else 0.0
        if self._lockstep is not None:      # a stop ends its waits (this loop's, ~step's)
            self._lockstep.stop_requested = stop_requested
        deadline, batch = time.monotonic(), self._batch
        while not rospy.is_shutdown() and not stop_requested():
            if not self.control.may_step():
                with self._lock:
                    step = self._step_info()
                    self._publish_faces(step, idle=True)
                    step.send_tf()
                    batch.flush()
                self.control.wait_until_may_step(_IDLE_SLEEP_S)
                deadline = time.monotonic()
                continue
            if self._lockstep is not None:
                self._lockstep.wait()      # the supervisor's answer to the last step
            with self._lock:
                if self.control.state != RUNNING:   # a pause or stop answered since may_step()
                    continue                        # wins: no step after its answer
                if self._lockstep is not None:
                    self._lockstep.stepped()
                self._guarded(self._step_and_publish)
                delay = 0.0
                if period_s > 0.0:
                    deadline += period_s
                    delay = deadline - time.monotonic()
                if (delay > 0.0 or batch.due() or self.control.synchronous
                        or self._lockstep is not None):
                    batch.flush()
            if delay > 0.0:
                time.sleep(max(0.0, deadline - time.monotonic()))
            elif delay < -_LAG_RESET_S:
                self._errors.warn("late", "the simulation fell %.2f s behind real time at "
                                  "t=%.3f s (a step took too long); that time is dropped, not "
                                  "caught up", -delay, self.sim.time_s)
                deadline = time.monotonic()


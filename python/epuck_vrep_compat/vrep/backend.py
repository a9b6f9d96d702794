"""V-REP's regular API (simGetObjectHandle, simGetObjectPosition, ...) over our scene.

Every call returns what V-REP returns, and a failure raises :class:`VrepError` with the reason;
the ``/vrep`` services turn it into V-REP's failure value and record the reason for
``simRosGetLastErrors``. Objects, their names, types and parents are the scene registry's;
what an object does comes from its components (``joint``, ``proximity``, ``vision``).
Callers hold the simulation lock: the core is not thread-safe.
"""
import collections
import functools
import math

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.sim.control import PAUSED, RUNNING, STOPPED
from epuck_vrep_compat.vrep.devices import VrepDevices
from epuck_vrep_compat.vrep.errors import VrepError  # noqa: F401  (the API's error, re-exported)
from epuck_vrep_compat.vrep.models import VrepModels
from epuck_vrep_compat.vrep.objects import VrepObjects
from epuck_vrep_compat.vrep.parameters import VrepParameters

MAX_ERRORS = 50            # the plugin keeps the last 50
MAX_ERROR_CHARS = 16384    # of one entry (a 10 kB name fits; a 1 MB string is cut)
MAX_SIGNALS = 10_000       # distinct names per kind (integer, float, string) set through /vrep


class ErrorLog:
    """The reasons of the last failed calls, for simRosGetLastErrors: the last
    :data:`MAX_ERRORS`, each cut at :data:`MAX_ERROR_CHARS` characters."""

    def __init__(self):
        self._errors = collections.deque(maxlen=MAX_ERRORS)

    def add(self, message: str):
        if len(message) > MAX_ERROR_CHARS:
            message = message[:MAX_ERROR_CHARS - 3] + "..."
        self._errors.append(message)

    def take(self):
        """All recorded errors, oldest first; the log is emptied (as simxGetLastErrors)."""
        errors = list(self._errors)
        self._errors.clear()
        return errors


def _part(part: str, method):
    """A backend method that calls ``method`` of the backend's part named ``part``."""
    @functools.wraps(method)
    def call(self, *args, **kwargs):
        return method(getattr(self, part), *args, **kwargs)
    return call


class VrepBackend:
    """V-REP's API on one simulation, as the ``/vrep`` services and streams call it: one flat
    set of calls, served by its parts (objects: :class:`VrepObjects`, joints and sensors:
    :class:`VrepDevices`, parameters: :class:`VrepParameters`, robots added and removed:
    :class:`VrepModels`) and by itself (signals, simulation state, the error log)."""

    def __init__(self, sim, control, real_time: bool, models=None):
        """``models``: the ModelLibrary simLoadModel reads (None: loading always fails)."""
        self.sim = sim
        self.control = control
        self._objects = VrepObjects(sim)
        self._devices = VrepDevices(self._objects)
        self._parameters = VrepParameters(self._objects, control, real_time)
        self._models = VrepModels(self._objects, models)
        self.errors = ErrorLog()
        self.signals = sim.signals          # the simulation's: the cell's scripts write some

    # --- objects -----------------------------------------------------------------------------
    object_handle = _part("_objects", VrepObjects.object_handle)
    object_name = _part("_objects", VrepObjects.object_name)
    object_type = _part("_objects", VrepObjects.object_type)
    objects = _part("_objects", VrepObjects.objects)
    parent = _part("_objects", VrepObjects.parent)
    child = _part("_objects", VrepObjects.child)
    selection = _part("_objects", VrepObjects.selection)
    set_selection = _part("_objects", VrepObjects.set_selection)
    pose = _part("_objects", VrepObjects.pose)
    set_pose = _part("_objects", VrepObjects.set_pose)
    velocity = _part("_objects", VrepObjects.velocity)

    # --- devices -----------------------------------------------------------------------------
    joint = _part("_devices", VrepDevices.joint)
    joints = _part("_devices", VrepDevices.joints)
    joint_state = _part("_devices", VrepDevices.joint_state)
    joint_command = _part("_devices", VrepDevices.joint_command)
    proximity = _part("_devices", VrepDevices.proximity)
    vision = _part("_devices", VrepDevices.vision)
    vision_image = _part("_devices", VrepDevices.vision_image)
    vision_depth = _part("_devices", VrepDevices.vision_depth)
    read_vision_sensor = _part("_devices", VrepDevices.read_vision_sensor)
    read_force_sensor = _part("_devices", VrepDevices.read_force_sensor)
    read_collision = _part("_devices", VrepDevices.read_collision)
    read_distance = _part("_devices", VrepDevices.read_distance)

    # --- parameters --------------------------------------------------------------------------
    boolean_parameter = _part("_parameters", VrepParameters.boolean_parameter)
    set_boolean_parameter = _part("_parameters", VrepParameters.set_boolean_parameter)
    floating_parameter = _part("_parameters", VrepParameters.floating_parameter)
    set_floating_parameter = _part("_parameters", VrepParameters.set_floating_parameter)
    integer_parameter = _part("_parameters", VrepParameters.integer_parameter)
    array_parameter = _part("_parameters", VrepParameters.array_parameter)
    string_parameter = _part("_parameters", VrepParameters.string_parameter)
    object_float_parameter = _part("_parameters", VrepParameters.object_float_parameter)
    object_int_parameter = _part("_parameters", VrepParameters.object_int_parameter)

    # --- models ------------------------------------------------------------------------------
    read_model = _part("_models", VrepModels.read_model)
    load_model = _part("_models", VrepModels.load_model)
    copy_paste = _part("_models", VrepModels.copy_paste)
    remove_object = _part("_models", VrepModels.remove_object)

    # --- signals ------------------------------------------------------------------------
    def signal(self, kind: str, name: str):
        try:
            return self.signals[kind][name]
        except KeyError:
            raise VrepError(f"{kind} signal '{name}' does not exist") from None

    def set_signal(self, kind: str, name: str, value):
        if not name:
            raise VrepError("signal name is empty")
        if kind == "float" and not math.isfinite(value):
            raise VrepError(f"float signal '{name}' value {value} is not finite")
        table = self.signals[kind]
        if name not in table and len(table) >= MAX_SIGNALS:
            raise VrepError(f"{kind} signal '{name}' not set: {MAX_SIGNALS} {kind} signals "
                            "exist (clear some first)")
        table[name] = value

    def clear_signal(self, kind: str, name: str = None) -> int:
        """Clear one signal, or all of a kind (name None); returns how many were cleared."""
        table = self.signals[kind]
        if name is None:
            count = len(table)
            table.clear()
            return count
        return 1 if table.pop(name, None) is not None else 0

    # --- simulation state ---------------------------------------------------------------
    @property
    def simulator_state(self) -> int:
        state = self.control.state
        bits = 0
        if state != STOPPED:
            bits |= vc.STATE_NOT_STOPPED
        if state == PAUSED:
            bits |= vc.STATE_PAUSED
        if self._parameters.real_time:
            bits |= vc.STATE_REAL_TIME
        return bits

    def info(self):
        """(frame id, simulator state bits, simulation time since start, time step)."""
        return (self.control.frame_id, self.simulator_state, self.control.time_since_start_s,
                self.sim.step_s)

    @property
    def running(self) -> bool:
        return self.control.state == RUNNING

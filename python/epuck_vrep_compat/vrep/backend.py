"""V-REP's regular API (simGetObjectHandle, simGetObjectPosition, ...) over our scene.

Every call returns what V-REP returns, and a failure raises :class:`VrepError` with the reason;
the ``/vrep`` services turn it into V-REP's failure value and record the reason for
``simRosGetLastErrors``. Objects, their names, types and parents are the scene registry's;
what an object does comes from its components (``joint``, ``proximity``, ``vision``).
Callers hold the simulation lock: the core is not thread-safe.
"""
import collections
import math

import numpy as np

from epuck_vrep_compat._core import WORLD_LIMIT_M
from epuck_vrep_compat.scene.transforms import compose, inverse, normalized_quat
from epuck_vrep_compat.sim.components import ComponentError
from epuck_vrep_compat.sim.control import PAUSED, RUNNING, STOPPED
from epuck_vrep_compat.vrep import constants as vc
from epuck_vrep_compat.vrep.errors import VrepError
from epuck_vrep_compat.vrep.models import VrepModels
from epuck_vrep_compat.vrep.parameters import VrepParameters

MAX_ERRORS = 50            # the plugin keeps the last 50


class ErrorLog:
    def __init__(self):
        self._errors = collections.deque(maxlen=MAX_ERRORS)

    def add(self, message: str):
        self._errors.append(message)

    def take(self):
        """All recorded errors, oldest first; the log is emptied (as simxGetLastErrors)."""
        errors = list(self._errors)
        self._errors.clear()
        return errors


class VrepBackend(VrepParameters, VrepModels):
    def __init__(self, sim, control, real_time: bool, models=None):
        """``models``: the ModelLibrary simLoadModel reads (None: loading always fails)."""
        self.sim = sim
        self.control = control
        self.real_time = real_time
        self.models = models
        self.errors = ErrorLog()
        self.signals = sim.signals          # the simulation's: the cell's scripts write some
        self._selection = []

    # --- objects ------------------------------------------------------------------------
    def _object(self, handle: int):
        try:
            return self.sim.registry.get(int(handle))
        except (KeyError, TypeError, ValueError):
            raise VrepError(f"object handle {handle} does not exist") from None

    def object_handle(self, name: str) -> int:
        """simGetObjectHandle: ``name#k`` is the copy with suffix k; a trailing ``#`` means
        the object without suffix (V-REP's notation for "no suffix")."""
        handle = self.sim.registry.handle_of(name[:-1] if name.endswith("#") else name)
        if handle < 0:
            raise VrepError(f"object '{name}' does not exist")
        return handle

    def object_name(self, handle: int) -> str:
        return self._object(handle).name

    def object_type(self, handle: int) -> int:
        return self._object(handle).object_type

    def objects(self, object_type: int):
        """Handles of all objects of a type (``sim_handle_all`` or 109: every object)."""
        everything = object_type in (vc.HANDLE_ALL, vc.APPOBJ_OBJECT)
        if not everything and not 0 <= object_type < vc.OBJECT_TYPE_END:
            raise VrepError(f"object type {object_type} is not valid")
        return [o.handle for o in self.sim.registry.objects()
                if everything or o.object_type == object_type]

    def parent(self, handle: int) -> int:
        return self._object(handle).parent

    def child(self, handle: int, index: int) -> int:
        """The index-th child, or -1 when there is none (not an error in V-REP)."""
        children = self.sim.registry.children(self._object(handle).handle)
        return children[index].handle if 0 <= index < len(children) else -1

    # --- selection ------------------------------------------------------------------------
    def selection(self):
        """simGetObjectSelection: the selected objects that still exist, in selection order."""
        return [h for h in self._selection if h in self.sim.registry]

    def set_selection(self, handles):
        """Clear the selection, then simAddObjectToSelection each handle; returns the handles
        that do not exist (skipped, each an error in V-REP)."""
        self._selection = []
        missing = []
        for handle in (int(h) for h in handles):
            if handle not in self.sim.registry:
                missing.append(handle)
            elif handle not in self._selection:
                self._selection.append(handle)
        return missing

    # --- poses --------------------------------------------------------------------------
    def _reference(self, handle: int, relative_to: int):
        """World pose of the frame ``relative_to`` refers to, or None for the world."""
        if relative_to == vc.WORLD:
            return None
        if relative_to == vc.HANDLE_PARENT:
            relative_to = self._object(handle).parent
            if relative_to == vc.WORLD:
                return None
        self._object(relative_to)
        return self.sim.registry.world_pose(relative_to)

    def pose(self, handle: int, relative_to: int = vc.WORLD):
        """(position (3), quaternion x, y, z, w) of an object in another's frame."""
        self._object(handle)
        position, quat = self.sim.registry.world_pose(handle)
        reference = self._reference(handle, relative_to)
        if reference is None:
            return position, quat
        inv_p, inv_q = inverse(*reference)
        return compose(inv_p, inv_q, position, quat)

    def set_pose(self, handle: int, relative_to: int, position=None, quat=None):
        """Move an object (a robot's base or a free scene object); parts of a robot model are
        rigid and refuse (V-REP would break the model). All or nothing: the whole request is
        checked (finite, within the world) before the scene is touched."""
        obj = self._object(handle)
        old_p, old_q = self.pose(handle, relative_to)
        new_p = old_p if position is None else np.asarray(position, dtype=float)
        if not np.all(np.isfinite(new_p)) or new_p.shape != (3,):
            raise VrepError(f"position {position} is not 3 finite numbers")
        new_q = old_q if quat is None else normalized_quat(quat)
        if new_q is None:
            raise VrepError(f"quaternion {quat} is zero or not finite")
        reference = self._reference(handle, relative_to)
        if reference is not None:
            new_p, new_q = compose(*reference, new_p, new_q)
        if not np.all(np.abs(new_p) <= WORLD_LIMIT_M):    # refused before anything is stored
            raise VrepError(f"position {np.asarray(new_p).tolist()} in the world frame is "
                            f"beyond ±{WORLD_LIMIT_M:g} m")
        try:
            self.sim.move_object(obj, new_p, new_q)
        except ValueError as e:
            raise VrepError(str(e)) from None

    def velocity(self, handle: int):
        """(linear (3), angular (3)) world velocity of an object (robots move, the rest is
        static)."""
        obj = self._object(handle)
        return self.sim.object_velocity(obj)

    # --- joints -------------------------------------------------------------------------
    def joint(self, handle: int):
        obj = self._object(handle)
        joint = obj.properties.get("joint")
        if obj.object_type != vc.OBJECT_JOINT or joint is None:
            raise VrepError(f"object {handle} ('{obj.name}') is not a joint")
        return joint

    def joints(self):
        return [o.handle for o in self.sim.registry.objects() if o.object_type == vc.OBJECT_JOINT]

    def joint_state(self, handle: int):
        joint = self.joint(handle)
        return joint.position(), joint.velocity(), joint.effort()

    def joint_command(self, handle: int, what: str, value: float):
        """``what`` is position, target_position, target_velocity or force."""
        value = float(value)
        if not math.isfinite(value):
            raise VrepError(f"joint {what} {value} is not finite")
        joint = self.joint(handle)
        try:
            getattr(joint, "set_" + what)(value)
        except ComponentError as e:
            raise VrepError(f"joint {handle}: {e}") from None

    # --- sensors ------------------------------------------------------------------------
    def proximity(self, handle: int):
        obj = self._object(handle)
        sensor = obj.properties.get("proximity")
        if sensor is None:
            raise VrepError(f"object {handle} ('{obj.name}') is not a proximity sensor")
        return sensor.read()

    def vision(self, handle: int):
        obj = self._object(handle)
        sensor = obj.properties.get("vision")
        if sensor is None:
            raise VrepError(f"object {handle} ('{obj.name}') is not a vision sensor")
        return sensor

    def vision_image(self, handle: int, mono: bool):
        """Image rows top first (ROS order): rgb (H, W, 3) or grey (H, W) = (r + g + b) / 3."""
        rgb, _ = self.vision(handle).render()
        if mono:
            return (rgb.astype(np.uint16).sum(axis=2) // 3).astype(np.uint8)
        return rgb

    def vision_depth(self, handle: int):
        """V-REP's depth buffer: (W, H), values 0..1 between the clipping planes, first row =
        bottom of the image (V-REP's order)."""
        sensor = self.vision(handle)
        _, depth = sensor.render()
        return sensor.resolution, _normalised_depth(sensor.spec, depth)[::-1].astype(np.float32)

    def read_vision_sensor(self, handle: int):
        """simReadVisionSensor: (detection state, auxiliary packets). Our sensors have V-REP's
        default filter, which triggers nothing (state 0) and gives packet 1 only: min, max and
        average of intensity, red, green, blue and depth, all in 0..1. A sensor with a blob
        filter adds packet 2: [blob count, 6, per blob size, orientation, x, y, width, height]."""
        sensor = self.vision(handle)
        rgb, depth = sensor.render()
        colour = rgb.reshape(-1, 3).astype(np.float64) / 255.0
        channels = np.column_stack((colour.mean(axis=1), colour,
                                    _normalised_depth(sensor.spec, depth).reshape(-1)))
        packet = np.concatenate((channels.min(axis=0), channels.max(axis=0),
                                 channels.mean(axis=0)))
        if getattr(sensor, "blob", False):
            # a blob detection filter (the cell's ceiling cameras): packet 2 is its output, and
            # it triggers detection while it finds a blob
            blobs = sensor.blob_packet()
            return int(blobs[0] > 0), [packet.tolist(), blobs.tolist()]
        return 0, [packet.tolist()]

    def read_force_sensor(self, handle: int):
        obj = self._object(handle)
        raise VrepError(f"object {handle} ('{obj.name}') is not a force sensor")

    def read_collision(self, handle: int):
        raise VrepError(f"collision object {handle} does not exist (the scene defines none)")

    def read_distance(self, handle: int):
        raise VrepError(f"distance object {handle} does not exist (the scene defines none)")

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
        self.signals[kind][name] = value

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
        if self.real_time:
            bits |= vc.STATE_REAL_TIME
        return bits

    def info(self):
        """(frame id, simulator state bits, simulation time since start, time step)."""
        return (self.control.frame_id, self.simulator_state, self.control.time_since_start_s,
                self.sim.step_s)

    @property
    def running(self) -> bool:
        return self.control.state == RUNNING


def _normalised_depth(spec, depth_m):
    """Depth along the axis [m] to V-REP's 0..1 between the near and far clipping planes."""
    normalised = (depth_m.astype(np.float64) - spec.near_m) / (spec.far_m - spec.near_m)
    return np.clip(normalised, 0.0, 1.0)

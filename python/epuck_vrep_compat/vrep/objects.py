"""V-REP's calls on scene objects: handles and names, types, hierarchy, selection, poses and
velocities, over the simulation's registry.

A part of :class:`~epuck_vrep_compat.vrep.backend.VrepBackend`; the other parts resolve handles
through :meth:`VrepObjects.get`. Failures raise :class:`VrepError` and change nothing.
"""
import numpy as np

from epuck_vrep_compat._core import WORLD_LIMIT_M
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import compose, inverse, normalized_quat
from epuck_vrep_compat.vrep.errors import VrepError


class VrepObjects:
    """The scene's objects as V-REP's API sees them (handles, names, parents, poses)."""

    def __init__(self, sim):
        self.sim = sim
        self._selected = []

    # --- objects ------------------------------------------------------------------------
    def get(self, handle: int):
        """The registry object of a handle; VrepError when there is none."""
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
        return self.get(handle).name

    def object_type(self, handle: int) -> int:
        return self.get(handle).object_type

    def objects(self, object_type: int):
        """Handles of all objects of a type (``sim_handle_all`` or 109: every object)."""
        everything = object_type in (vc.HANDLE_ALL, vc.APPOBJ_OBJECT)
        if not everything and not 0 <= object_type < vc.OBJECT_TYPE_END:
            raise VrepError(f"object type {object_type} is not valid")
        return [o.handle for o in self.sim.registry.objects()
                if everything or o.object_type == object_type]

    def parent(self, handle: int) -> int:
        return self.get(handle).parent

    def child(self, handle: int, index: int) -> int:
        """The index-th child, or -1 when there is none (not an error in V-REP)."""
        children = self.sim.registry.children(self.get(handle).handle)
        return children[index].handle if 0 <= index < len(children) else -1

    # --- selection ------------------------------------------------------------------------
    def selection(self):
        """simGetObjectSelection: the selected objects that still exist, in selection order."""
        return [h for h in self._selected if h in self.sim.registry]

    def set_selection(self, handles):
        """Clear the selection, then simAddObjectToSelection each handle; returns the handles
        that do not exist (skipped, each an error in V-REP)."""
        self._selected = []
        missing = []
        for handle in (int(h) for h in handles):
            if handle not in self.sim.registry:
                missing.append(handle)
            elif handle not in self._selected:
                self._selected.append(handle)
        return missing

    # --- poses --------------------------------------------------------------------------
    def _reference(self, handle: int, relative_to: int):
        """World pose of the frame ``relative_to`` refers to, or None for the world."""
        if relative_to == vc.WORLD:
            return None
        if relative_to == vc.HANDLE_PARENT:
            relative_to = self.get(handle).parent
            if relative_to == vc.WORLD:
                return None
        self.get(relative_to)
        return self.sim.registry.world_pose(relative_to)

    def pose(self, handle: int, relative_to: int = vc.WORLD):
        """(position (3), quaternion x, y, z, w) of an object in another's frame."""
        self.get(handle)
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
        obj = self.get(handle)
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
        obj = self.get(handle)
        return self.sim.object_velocity(obj)

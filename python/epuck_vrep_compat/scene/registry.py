"""The one registry of scene objects: stable integer handle, V-REP-style name, parent, pose.

Every simulated thing (arena part, robot, link, joint, sensor, camera) is registered here. Object
type codes are V-REP's (``sim_object_*_type``) so the ``/vrep`` services can answer with them.
Poses are stored relative to the parent; an object whose pose changes every step (a robot base,
a wheel) has a *pose source* that the simulation supplies, so nothing is copied per step: the
world pose is composed along the parent chain only when someone asks.
"""
from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional, Tuple

import numpy as np

from epuck_vrep_compat.compat.vrep_codes import WORLD
from epuck_vrep_compat.geometry.transforms import IDENTITY_QUAT, compose

PoseSource = Callable[[], Tuple[np.ndarray, np.ndarray]]


@dataclass
class SceneObject:
    """One object of the scene, as V-REP's API sees it: handle, name, type, parent, pose
    (stored or from a pose source), owner robot and its components (``properties``)."""
    handle: int
    name: str
    object_type: int
    parent: int
    local_position: np.ndarray
    local_quat: np.ndarray
    pose_source: Optional[PoseSource] = None     # overrides the stored local pose
    robot: Optional[str] = None                  # robot this object belongs to
    part: Optional[str] = None                   # model part key, e.g. "proxSensor3"
    properties: dict = field(default_factory=dict)

    def local_pose(self):
        if self.pose_source is not None:
            return self.pose_source()
        return self.local_position, self.local_quat


class SceneRegistry:
    """Objects by handle and by name; handles are given in creation order from 1 upwards."""

    def __init__(self):
        self._objects: Dict[int, SceneObject] = {}
        self._by_name: Dict[str, int] = {}
        self._next_handle = 1

    def add(self, name: str, object_type: int, parent: int = WORLD, position=(0.0, 0.0, 0.0),
            quat=IDENTITY_QUAT, **kwargs) -> SceneObject:
        if name in self._by_name:
            raise ValueError(f"object name '{name}' is already used")
        if parent != WORLD and parent not in self._objects:
            raise KeyError(f"parent handle {parent} does not exist")
        obj = SceneObject(self._next_handle, name, object_type, parent,
                          np.asarray(position, dtype=float), np.asarray(quat, dtype=float),
                          **kwargs)
        self._objects[obj.handle] = obj
        self._by_name[name] = obj.handle
        self._next_handle += 1
        return obj

    def __len__(self):
        return len(self._objects)

    def __contains__(self, handle: int) -> bool:
        return handle in self._objects

    def get(self, handle: int) -> SceneObject:
        return self._objects[handle]

    def handle_of(self, name: str) -> int:
        """V-REP semantics: the handle, or -1 when no object has that name."""
        return self._by_name.get(name, -1)

    def objects(self) -> List[SceneObject]:
        return list(self._objects.values())

    def children(self, handle: int) -> List[SceneObject]:
        return [o for o in self._objects.values() if o.parent == handle]

    def remove(self, handle: int) -> List[int]:
        """Remove an object and its descendants; returns the removed handles."""
        removed = [handle]
        for child in self.children(handle):
            removed += self.remove(child.handle)
        obj = self._objects.pop(handle)
        del self._by_name[obj.name]
        return removed

    def world_pose(self, handle: int):
        obj = self._objects[handle]
        position, quat = obj.local_pose()
        while obj.parent != WORLD:
            obj = self._objects[obj.parent]
            parent_position, parent_quat = obj.local_pose()
            position, quat = compose(parent_position, parent_quat, position, quat)
        return np.asarray(position, dtype=float), np.asarray(quat, dtype=float)

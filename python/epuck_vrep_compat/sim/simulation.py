"""The simulation: one scene registry, one collision world, the arena, and the extensions that
bring robots into it.

ROS-free. The ROS faces read its state after each step and write commands into it (commands ->
step -> state arrays -> faces, one way per step).

The simulation knows no robot family: every robot (the e-pucks, the industrial cell) comes in
as an extension (:class:`~epuck_vrep_compat.sim.extension.SimulationExtension`), added by
the builder, called in the order it was added and never named. Objects can be added and removed
between steps, by a caller that holds the simulation lock (:attr:`Simulation.lock`: the core is
not thread-safe); afterwards every listener is called (:meth:`Simulation.objects_changed`), so
the faces follow. Handles never change: a removed object's handle is never given again.
"""
import math
import threading
from typing import Callable, List

import numpy as np

from epuck_vrep_compat._core import CollisionWorld
from epuck_vrep_compat.sim.extension import SimulationExtension
from epuck_vrep_compat.scene import registry as reg
from epuck_vrep_compat.scene.scene_file import Scene
from epuck_vrep_compat.sim.arena import build_arena

STEP_S = 0.05           # the default step: V-REP's 50 ms
SEED = 0                # the default seed of every random stream


class Simulation:
    """The simulated world the ROS faces and the V-REP API read and drive: the scene registry,
    the core's collision world, the arena's obstacles, V-REP's signals, simulated time, and the
    extensions (:attr:`extensions`) that hold the robots."""

    def __init__(self, scene: Scene, step_s: float = STEP_S, seed: int = SEED,
                 extended_sections=()):
        """``extended_sections``: the scene's sections that extensions build (the builder's
        word); any other is refused (SceneError). ``seed``: the one seed the builder derives
        every random stream of the extensions from."""
        scene.refuse_unbuilt(extended_sections)
        if step_s <= 0.0 or not math.isfinite(step_s):
            raise ValueError(f"step_s must be a positive number, got {step_s}")
        self.scene = scene
        self.step_s = float(step_s)
        self.seed = int(seed)
        self.registry = reg.SceneRegistry()
        self.world = CollisionWorld()
        self.obstacles = build_arena(scene, self.registry, self.world)
        self.lock = threading.RLock()       # steps, scene changes, every command; reentrant
        # V-REP's signals: named values that scripts (the cell's) and clients share, by kind
        self.signals = {"int": {}, "float": {}, "string": {}}
        self.listeners: List[Callable[[], None]] = []
        self.frame = 0
        self.extensions: List[SimulationExtension] = []

    def add_extension(self, extension: SimulationExtension):
        """From now on the simulation calls ``extension``'s hooks (after those added before)."""
        self.extensions.append(extension)

    def _owner(self, obj):
        """The extension that owns ``obj``, or None."""
        return next((e for e in self.extensions if e.owns(obj)), None)

    # --- objects added, removed and moved ---------------------------------------------------
    def objects_changed(self):
        """Robots or objects came or went: every listener is called (the faces follow)."""
        for listener in list(self.listeners):
            listener()

    def load_model(self, model):
        """simLoadModel of a model file (``scene.model_files.ModelFile``): the new robot from
        the first extension that loads such models (see
        :meth:`SimulationExtension.load_model`), then the listeners are called; None when no
        extension loads it. ValueError (nothing changed) when refused."""
        for extension in self.extensions:
            robot = extension.load_model(model)
            if robot is not None:
                self.objects_changed()
                return robot
        return None

    def remove_object(self, handle: int) -> List[int]:
        """Remove a scene object with its children; an extension's object as the extension
        says (:meth:`SimulationExtension.claims_removal`: a robot's base object takes the whole
        robot); returns the removed handles. KeyError for an unknown handle; ValueError for a
        part of a robot (a robot is removed whole)."""
        obj = self.registry.get(handle)
        for extension in self.extensions:
            if extension.claims_removal(obj):
                removed = self._remove_subtree(handle)
                extension.forget(set(removed))
                self.objects_changed()
                return removed
        removed = self._remove_subtree(handle)
        self.objects_changed()
        return removed

    def _remove_subtree(self, handle: int) -> List[int]:
        """An object and its descendants out of the registry and the collision world."""
        removed = self.registry.remove(handle)
        for h in removed:
            if self.world.has(h):
                self.world.remove(h)
        return removed

    def live_obstacles(self):
        """The scene's obstacles that have not been removed."""
        return [o for o, handle in self.obstacles if handle in self.registry]

    def move_object(self, obj, position, quat):
        """Teleport an object: an extension's as the extension allows (a robot by its base
        object), a free scene object anywhere. A refused pose (ValueError) leaves everything as
        it was."""
        owner = self._owner(obj)
        if owner is not None:
            owner.move_object(obj, position, quat)
            return
        position = np.asarray(position, dtype=float)
        quat = np.asarray(quat, dtype=float)
        if self.world.has(obj.handle):      # first: the core refuses a bad pose (ValueError)
            self.world.set_pose(obj.handle, position, quat)
        obj.local_position, obj.local_quat = position, quat

    def object_velocity(self, obj):
        """(linear (3), angular (3)) in the world frame; static objects stand still."""
        owner = self._owner(obj)
        if owner is not None:
            return owner.object_velocity(obj)
        return np.zeros(3), np.zeros(3)

    def published_signals(self):
        """Every extension's :meth:`SimulationExtension.published_signals`, in their order."""
        return [signal for e in self.extensions for signal in e.published_signals()]

    # --- stepping ------------------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        return self.frame * self.step_s

    def step(self):
        """One step: the frame advances, then every extension steps in the order added (the
        builder's: the e-pucks first); afterwards their state arrays hold this step's
        readings."""
        self.frame += 1
        for extension in self.extensions:
            extension.step(self.step_s)

    def reset(self):
        """Every extension back to its start, in the order added (robots at their start poses,
        commands cleared, noise streams restarted)."""
        for extension in self.extensions:
            extension.reset()

    def rewind(self):
        """Back to time 0 (frame 0), then :meth:`reset`: the world as it was built, for clients
        that start again with it (time goes back, which :meth:`reset` alone never does)."""
        self.frame = 0
        self.reset()

"""The simulation: one scene registry, one collision world, one batched e-puck swarm.

ROS-free. The ROS faces read its state after each step and write commands into it (commands ->
core step -> sensor arrays -> adapters, one way per step).

Robots and scene objects can be added and removed between steps, by a caller that holds the
simulation lock (:attr:`Simulation.lock`: the core is not thread-safe); afterwards every
listener is called, so the faces follow. Robot rows (``robot_names``, ``robots``,
``start_poses``, the command arrays and the core's outputs) stay in step: a removal shifts the
later rows up by one. Handles never change: a removed object's handle is never given again.
Wheel commands arrive on other threads by robot name, under a lock of their own (no step wait).

What the e-pucks' arena does not hold (the industrial cell) comes in as an extension
(:class:`~epuck_vrep_compat.devices.extension.SimulationExtension`): called, never named.
"""
import math
import threading
from dataclasses import dataclass
from typing import Callable, List, Sequence

import numpy as np

from epuck_vrep_compat._core import CollisionWorld, EpuckSwarm
from epuck_vrep_compat.compat.epuck_names import VREP
from epuck_vrep_compat.devices.components import CameraSpec
from epuck_vrep_compat.devices.extension import SimulationExtension
from epuck_vrep_compat.epuck.components import attach_components
from epuck_vrep_compat.epuck.leds import RobotLeds
from epuck_vrep_compat.epuck.noise import NoiseSettings
from epuck_vrep_compat.geometry.transforms import quat_from_yaw, yaw_of
from epuck_vrep_compat.scene import registry as reg
from epuck_vrep_compat.scene.epuck_model import (
    RobotParts, default_model, next_robot_number, register_epuck)
from epuck_vrep_compat.scene.placement import free_place, place_robots
from epuck_vrep_compat.scene.scene_file import Scene
from epuck_vrep_compat.sim.arena import build_arena


@dataclass
class RobotCommand:
    """Where a robot's wheel speeds came from, for the command watchdog."""

    wheel_rad_s: np.ndarray       # (N, 2)
    stamp_s: np.ndarray           # (N,) simulation time of the last command, -inf = never


class Simulation:
    """The simulated world the ROS faces and the V-REP API read and drive: the scene registry,
    the core's collision world and e-puck swarm, the robots' commands, and the extensions
    (:attr:`extensions`) that add more to the scene."""

    def __init__(self, scene: Scene, robot_names: Sequence[str], step_s: float = 0.05,
                 seed: int = 0, noise: NoiseSettings = None, cmd_timeout_s: float = 1.0,
                 camera: CameraSpec = None, robot_namer: Callable[[int], str] = None,
                 extended_sections: Sequence[str] = ()):
        """``robot_namer`` names robot number k (suffix ``#k-1``) added later; by default
        ``ePuck<k>``, as the V-REP model's script. ``extended_sections``: the scene's sections
        that extensions build (the builder's word); any other is refused (SceneError)."""
        scene.refuse_unbuilt(extended_sections)
        if step_s <= 0.0 or not math.isfinite(step_s):
            raise ValueError(f"step_s must be a positive number, got {step_s}")
        self.scene = scene
        self.step_s = float(step_s)
        self.seed = int(seed)
        self.cmd_timeout_s = float(cmd_timeout_s)
        self.camera = camera if camera is not None else CameraSpec()
        self.robot_namer = robot_namer if robot_namer is not None else VREP.robot_name
        self.model = default_model()
        self.registry = reg.SceneRegistry()
        self.world = CollisionWorld()
        self.obstacles = build_arena(scene, self.registry, self.world)
        self.swarm = EpuckSwarm(self.world, self.model, self.seed)
        self.robots: List[RobotParts] = []
        self.robot_names: List[str] = []
        self.start_poses = []
        self._index_by_name = {}
        self.lock = threading.RLock()       # steps, scene changes, the cell's commands; reentrant
        self._commands_lock = threading.Lock()
        self.command = RobotCommand(np.zeros((0, 2)), np.zeros(0))
        self.leds = RobotLeds()          # set by cmd_led, read by the LED face
        # V-REP's signals: named values that scripts (the cell's) and clients share, by kind
        self.signals = {"int": {}, "float": {}, "string": {}}
        self.listeners: List[Callable[[], None]] = []
        starts = place_robots(scene, len(robot_names), self.model.body_radius_m)
        for number, (name, pose) in enumerate(zip(robot_names, starts)):
            self._add(number, name, pose)
        self.noise = noise if noise is not None else NoiseSettings()
        self.noise.apply(self.swarm, self.robot_names)
        self.frame = 0
        self._refresh()
        self.extensions: List[SimulationExtension] = []

    def add_extension(self, extension: SimulationExtension):
        """From now on the simulation calls ``extension``'s hooks (after those added before)."""
        self.extensions.append(extension)

    def _owner(self, obj):
        """The extension that owns ``obj``, or None."""
        return next((e for e in self.extensions if e.owns(obj)), None)

    # --- robots and objects added and removed ---------------------------------------------
    def add_robot(self, near_xy=(0.0, 0.0), yaw_rad: float = 0.0) -> RobotParts:
        """A new e-puck at the free place nearest ``near_xy``, named as V-REP names a pasted
        model (:func:`next_robot_number`). SceneError when no place is free."""
        number = next_robot_number(o.name for o in self.registry.objects())
        name = self.robot_namer(number)
        if name in self._index_by_name:
            raise ValueError(f"a robot named '{name}' exists already")
        occupied = np.vstack((self.swarm.poses[:, :2],
                              np.reshape(self.start_poses, (-1, 3))[:, :2]))
        x, y = free_place(self.scene, self.live_obstacles(), occupied,
                          self.model.body_radius_m, near_xy)
        parts = self._add(number, name, (x, y, float(yaw_rad)))
        self.noise.apply(self.swarm, self.robot_names)
        self._changed()
        return parts

    def remove_robot(self, name: str) -> List[int]:
        """Remove a robot with all its objects; returns their handles. KeyError if unknown."""
        index = self._index_by_name[name]
        parts = self.robots[index]
        with self._commands_lock:
            del self.robots[index], self.robot_names[index], self.start_poses[index]
            self._index_by_name = {n: i for i, n in enumerate(self.robot_names)}
            self.command = RobotCommand(np.delete(self.command.wheel_rad_s, index, axis=0),
                                        np.delete(self.command.stamp_s, index))
        self.leds.remove(name)
        self.swarm.remove_robot(index)
        removed = self.registry.remove(parts.root.handle)
        self._changed()
        return removed

    def remove_object(self, handle: int) -> List[int]:
        """Remove a scene object (with its children) or, for a robot's base object, the whole
        robot (an extension's objects: see :meth:`SimulationExtension.claims_removal`);
        returns the removed handles. KeyError for an unknown handle; ValueError for a part of a
        robot (a robot is removed whole)."""
        obj = self.registry.get(handle)
        for extension in self.extensions:
            if extension.claims_removal(obj):
                removed = self._remove_subtree(handle)
                extension.forget(set(removed))
                self._changed()
                return removed
        if obj.robot is not None:
            if obj.part != "root":
                base = self.robots[self._index_by_name[obj.robot]].root.name
                raise ValueError(f"'{obj.name}' is part of robot {obj.robot}; remove the "
                                 f"robot's base object '{base}' instead")
            return self.remove_robot(obj.robot)
        removed = self._remove_subtree(handle)
        self._changed()
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

    def _add(self, number, name, pose) -> RobotParts:
        x, y, yaw = pose
        parts = register_epuck(self.registry, self.model, number, name,
                               self._root_pose_source(name), self._wheel_angle_source(name))
        self.swarm.add_robot(parts.root.handle, x, y, yaw)
        index = self.swarm.size - 1
        self.swarm.set_odometry(index, x, y, yaw)
        attach_components(self, name, parts)
        with self._commands_lock:
            self.robots.append(parts)
            self.robot_names.append(name)
            self.start_poses.append((x, y, yaw))
            self._index_by_name[name] = index
            self.command = RobotCommand(np.vstack((self.command.wheel_rad_s, np.zeros((1, 2)))),
                                        np.append(self.command.stamp_s, -np.inf))
        self.leds.add(name)
        return parts

    def _root_pose_source(self, name):
        def pose():
            x, y, yaw = self._poses[self._index_by_name[name]]
            return np.array([x, y, 0.0]), quat_from_yaw(yaw)
        return pose

    def _wheel_angle_source(self, name):
        return lambda: self._wheel_angles[self._index_by_name[name]]

    def _changed(self):
        self._refresh()
        for listener in list(self.listeners):
            listener()

    def _refresh(self):
        self._poses = self.swarm.poses
        self._wheel_angles = self.swarm.wheel_angles

    # --- commands (from the ROS faces) --------------------------------------------------------
    def robot_index(self, name: str) -> int:
        """Index of a robot by name; -1 when there is no such robot."""
        return self._index_by_name.get(name, -1)

    def set_wheel_speeds(self, name: str, left_rad_s: float, right_rad_s: float) -> bool:
        """Command a robot's wheels; non-finite values are refused (returns False). A robot
        that no longer exists ignores it."""
        if not (math.isfinite(left_rad_s) and math.isfinite(right_rad_s)):
            return False
        with self._commands_lock:
            index = self._index_by_name.get(name)
            if index is not None:
                self.command.wheel_rad_s[index] = (left_rad_s, right_rad_s)
                self.command.stamp_s[index] = self.time_s
        return True

    def set_wheel_speed(self, name: str, column: int, rad_s: float):
        """One wheel's speed, as a joint command: it persists (no cmd_vel watchdog)."""
        with self._commands_lock:
            index = self._index_by_name[name]
            self.command.wheel_rad_s[index, column] = rad_s
            self.command.stamp_s[index] = np.inf

    def move_object(self, obj, position, quat):
        """Teleport a robot (its base object: x, y and yaw; robots stay on the ground) or a
        free scene object. Parts of a robot are rigid: ValueError. A refused pose (ValueError)
        leaves everything as it was."""
        owner = self._owner(obj)
        if owner is not None:
            owner.move_object(obj, position, quat)
            return
        if obj.robot is not None:
            if obj.part != "root":
                raise ValueError(f"'{obj.name}' is part of robot {obj.robot}; move the robot's "
                                 "base object instead")
            i = self._index_by_name[obj.robot]
            self.swarm.set_pose(i, float(position[0]), float(position[1]),
                                float(yaw_of(quat)))
            self._refresh()
            return
        position = np.asarray(position, dtype=float)
        quat = np.asarray(quat, dtype=float)
        if self.world.has(obj.handle):      # first: the core refuses a bad pose (ValueError)
            self.world.set_pose(obj.handle, position, quat)
        obj.local_position, obj.local_quat = position, quat

    def object_velocity(self, obj):
        """(linear (3), angular (3)) in the world frame; robot parts move with their robot."""
        owner = self._owner(obj)
        if owner is not None:
            return owner.object_velocity(obj)
        if obj.robot is None:
            return np.zeros(3), np.zeros(3)
        vx, vy, wz = self.swarm.velocities[self._index_by_name[obj.robot]]
        return np.array([vx, vy, 0.0]), np.array([0.0, 0.0, wz])

    def published_signals(self):
        """Every extension's :meth:`SimulationExtension.published_signals`, in their order."""
        return [signal for e in self.extensions for signal in e.published_signals()]

    # --- stepping ------------------------------------------------------------------------------
    @property
    def time_s(self) -> float:
        return self.frame * self.step_s

    @property
    def size(self) -> int:
        return len(self.robot_names)

    def step(self):
        """One physics step; afterwards the swarm's sensor arrays hold this step's readings."""
        if self.cmd_timeout_s > 0.0:
            stale = (self.time_s - self.command.stamp_s) > self.cmd_timeout_s
            self.command.wheel_rad_s[stale] = 0.0
        self.swarm.step(self.step_s, self.command.wheel_rad_s)
        self.frame += 1
        for extension in self.extensions:
            extension.step(self.step_s)
        self._refresh()

    def reset(self):
        """Robots back to their start poses (a robot added later: where it was placed),
        commands cleared, noise streams restarted."""
        for i, (x, y, yaw) in enumerate(self.start_poses):
            self.swarm.set_pose(i, x, y, yaw)
            self.swarm.set_odometry(i, x, y, yaw)
        with self._commands_lock:
            self.command.wheel_rad_s[:] = 0.0
            self.command.stamp_s[:] = -np.inf
        self.swarm.reseed(self.seed)
        self._refresh()
        for extension in self.extensions:
            extension.reset()

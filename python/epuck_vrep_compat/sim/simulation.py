"""The simulation: one scene registry, one collision world, one batched e-puck swarm.

ROS-free. The ROS faces read its state after each step and write commands into it; data flows
one way per step (commands -> core step -> sensor arrays -> adapters).
"""
import math
from dataclasses import dataclass
from typing import List, Sequence

import numpy as np

from epuck_vrep_compat._core import (
    GROUP_FLOOR, GROUP_STATIC, CollisionWorld, EpuckSwarm)
from epuck_vrep_compat.scene import registry as reg
from epuck_vrep_compat.scene.epuck_model import RobotParts, default_model, register_epuck
from epuck_vrep_compat.scene.placement import place_robots
from epuck_vrep_compat.scene.scene_file import Scene
from epuck_vrep_compat.scene.transforms import quat_from_yaw, yaw_of
from epuck_vrep_compat.sim.components import CameraSpec, ConeProximity, VisionSensor, WheelJoint
from epuck_vrep_compat.sim.noise import NoiseSettings

FLOOR_THICKNESS_M = 0.01


@dataclass
class RobotCommand:
    """Where a robot's wheel speeds came from, for the command watchdog."""

    wheel_rad_s: np.ndarray       # (N, 2)
    stamp_s: np.ndarray           # (N,) simulation time of the last command, -inf = never


class Simulation:
    def __init__(self, scene: Scene, robot_names: Sequence[str], step_s: float = 0.05,
                 seed: int = 0, noise: NoiseSettings = None, cmd_timeout_s: float = 1.0,
                 camera: CameraSpec = None):
        if step_s <= 0.0 or not math.isfinite(step_s):
            raise ValueError(f"step_s must be a positive number, got {step_s}")
        self.scene = scene
        self.step_s = float(step_s)
        self.seed = int(seed)
        self.cmd_timeout_s = float(cmd_timeout_s)
        self.robot_names: List[str] = list(robot_names)
        self.camera = camera if camera is not None else CameraSpec()
        self.model = default_model()
        self.registry = reg.SceneRegistry()
        self.world = CollisionWorld()
        self._build_arena()
        self.swarm = EpuckSwarm(self.world, self.model, self.seed)
        self.robots: List[RobotParts] = []
        self._index_by_name = {name: i for i, name in enumerate(self.robot_names)}
        self.start_poses = place_robots(scene, len(self.robot_names), self.model.body_radius_m)
        for i, name in enumerate(self.robot_names):
            parts = register_epuck(self.registry, self.model, i, name,
                                   self._root_pose_source(i), self._wheel_angle_source(i))
            x, y, yaw = self.start_poses[i]
            self.swarm.add_robot(parts.root.handle, x, y, yaw)
            self.swarm.set_odometry(i, x, y, yaw)
            self._attach_components(i, parts)
            self.robots.append(parts)
        n = len(self.robot_names)
        self.command = RobotCommand(np.zeros((n, 2)), np.full(n, -np.inf))
        self.noise = noise if noise is not None else NoiseSettings()
        self.noise.apply(self.swarm, n)
        self.frame = 0
        self._poses = self.swarm.poses
        self._wheel_angles = self.swarm.wheel_angles
        self.cell = None
        if scene.cell is not None:
            from epuck_vrep_compat.cell.cell import Cell     # pybullet only when a cell is used
            self.cell = Cell(self, scene.cell, self.seed)

    # --- construction -----------------------------------------------------------------------
    def _build_arena(self):
        arena = self.scene.arena
        sx, sy = arena.size_m
        h, t = arena.wall_height_m, arena.wall_thickness_m
        self._add_box(arena.floor_name, (sx + 2 * t, sy + 2 * t, FLOOR_THICKNESS_M),
                      (0.0, 0.0, -0.5 * FLOOR_THICKNESS_M), 0.0, arena.floor_color, GROUP_FLOOR)
        walls = (((sx + 2 * t, t, h), (0.0, 0.5 * (sy + t))),
                 ((sx + 2 * t, t, h), (0.0, -0.5 * (sy + t))),
                 ((t, sy, h), (0.5 * (sx + t), 0.0)),
                 ((t, sy, h), (-0.5 * (sx + t), 0.0)))
        for k, (size, (x, y)) in enumerate(walls):
            self._add_box(f"Wall{k}", size, (x, y, 0.5 * h), 0.0, arena.wall_color, GROUP_STATIC)
        for o in self.scene.obstacles:
            x, y = o.position_m
            if o.shape == "box":
                self._add_box(o.name, o.size_m, (x, y, 0.5 * o.size_m[2]), o.yaw_rad, o.color,
                              GROUP_STATIC)
            else:
                quat = quat_from_yaw(o.yaw_rad)
                size = (2.0 * o.radius_m, 2.0 * o.radius_m, o.height_m)
                obj = self.registry.add(o.name, reg.SHAPE, reg.WORLD, (x, y, 0.5 * o.height_m),
                                        quat, properties=dict(shape="cylinder", size=size,
                                                              color=o.color))
                self.world.add_cylinder(obj.handle, o.radius_m, o.height_m,
                                        obj.local_position, quat, o.color, GROUP_STATIC)

    def _add_box(self, name, size, position, yaw, color, group):
        quat = quat_from_yaw(yaw)
        obj = self.registry.add(name, reg.SHAPE, reg.WORLD, position, quat,
                                properties=dict(shape="box", size=tuple(size), color=color))
        self.world.add_box(obj.handle, 0.5 * np.asarray(size, dtype=float),
                           np.asarray(position, dtype=float), quat, color, group)

    def _attach_components(self, i, parts):
        for column, side in enumerate(("left", "right")):
            parts.parts[f"{side}Joint"].properties["joint"] = WheelJoint(self, i, column)
        for k in range(len(self.model.sensors)):
            parts.parts[f"proxSensor{k}"].properties["proximity"] = ConeProximity(self, i, k)
        parts.parts["camera"].properties["vision"] = VisionSensor(
            self, parts.handle("camera"), self.camera, ignore_handle=parts.root.handle)

    def _root_pose_source(self, i):
        def pose():
            x, y, yaw = self._poses[i]
            return np.array([x, y, 0.0]), quat_from_yaw(yaw)
        return pose

    def _wheel_angle_source(self, i):
        return lambda: self._wheel_angles[i]

    # --- commands (from the ROS faces) --------------------------------------------------------
    def robot_index(self, name: str) -> int:
        """Index of a robot by name; -1 when there is no such robot."""
        return self._index_by_name.get(name, -1)

    def set_wheel_speeds(self, index: int, left_rad_s: float, right_rad_s: float) -> bool:
        """Command a robot's wheels; non-finite values are refused (returns False)."""
        if not (math.isfinite(left_rad_s) and math.isfinite(right_rad_s)):
            return False
        self.command.wheel_rad_s[index] = (left_rad_s, right_rad_s)
        self.command.stamp_s[index] = self.time_s
        return True

    def set_wheel_speed(self, index: int, column: int, rad_s: float):
        """One wheel's speed, as a joint command: it persists (no cmd_vel watchdog)."""
        self.command.wheel_rad_s[index, column] = rad_s
        self.command.stamp_s[index] = np.inf

    def move_object(self, obj, position, quat):
        """Teleport a robot (its base object: x, y and yaw; robots stay on the ground) or a
        free scene object. Parts of a robot are rigid: ValueError."""
        if self.cell is not None and self.cell.owns(obj):
            self.cell.move_object(obj, position, quat)
            return
        if obj.robot is not None:
            if obj.part != "root":
                raise ValueError(f"'{obj.name}' is part of robot {obj.robot}; move the robot's "
                                 "base object instead")
            i = self._index_by_name[obj.robot]
            self.swarm.set_pose(i, float(position[0]), float(position[1]),
                                float(yaw_of(quat)))
            self._poses = self.swarm.poses
            return
        obj.local_position = np.asarray(position, dtype=float)
        obj.local_quat = np.asarray(quat, dtype=float)
        if self.world.has(obj.handle):
            self.world.set_pose(obj.handle, obj.local_position, obj.local_quat)

    def object_velocity(self, obj):
        """(linear (3), angular (3)) in the world frame; robot parts move with their robot."""
        if self.cell is not None and self.cell.owns(obj):
            return self.cell.object_velocity(obj)
        if obj.robot is None:
            return np.zeros(3), np.zeros(3)
        vx, vy, wz = self.swarm.velocities[self._index_by_name[obj.robot]]
        return np.array([vx, vy, 0.0]), np.array([0.0, 0.0, wz])

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
        if self.cell is not None:
            self.cell.step(self.step_s)
        self._poses = self.swarm.poses
        self._wheel_angles = self.swarm.wheel_angles

    def reset(self):
        """Robots back to their start poses, commands cleared, noise streams restarted."""
        for i, (x, y, yaw) in enumerate(self.start_poses):
            self.swarm.set_pose(i, x, y, yaw)
            self.swarm.set_odometry(i, x, y, yaw)
        self.command.wheel_rad_s[:] = 0.0
        self.command.stamp_s[:] = -np.inf
        self.swarm.reseed(self.seed)
        self._poses = self.swarm.poses
        self._wheel_angles = self.swarm.wheel_angles
        if self.cell is not None:
            self.cell.reset()

"""The e-pucks of a simulation: the core's batched swarm, the robots' rows, their wheel commands
with the ``cmd_vel`` watchdog, their LEDs and noise, as an extension of the simulation.

Robot rows (``robot_names``, ``robots``, ``start_poses``, the command arrays and the core's
outputs) stay in step: a removal shifts the later rows up by one. Wheel commands arrive on other
threads by robot name, under a lock of their own (no step wait); robots come and go under the
simulation lock, added here (:meth:`EpuckRobots.add_robot`, a model loaded) and removed through
the simulation (:meth:`EpuckRobots.remove_robot`, an object removed), which then calls its
listeners.
"""
import math
import threading
from dataclasses import dataclass
from typing import Callable, List, Sequence

import numpy as np

from epuck_vrep_compat._core import EpuckSwarm
from epuck_vrep_compat.compat.epuck_names import VREP
from epuck_vrep_compat.devices.components import CameraSpec
from epuck_vrep_compat.sim.extension import SimulationExtension
from epuck_vrep_compat.epuck.components import attach_components
from epuck_vrep_compat.epuck.leds import RobotLeds
from epuck_vrep_compat.epuck.noise import NoiseSettings
from epuck_vrep_compat.geometry.transforms import quat_from_yaw, yaw_of
from epuck_vrep_compat.scene.epuck_model import (
    RobotParts, default_model, next_robot_number, register_epuck)
from epuck_vrep_compat.scene.placement import free_place, place_robots

CMD_TIMEOUT_S = 1.0     # the default watchdog: a robot stops 1 s after its last cmd_vel
MODEL_KIND = "epuck"    # the model files' ``robot:`` this extension loads


@dataclass
class RobotCommand:
    """Where a robot's wheel speeds came from, for the command watchdog."""

    wheel_rad_s: np.ndarray       # (N, 2)
    stamp_s: np.ndarray           # (N,) simulation time of the last command, -inf = never


class EpuckRobots(SimulationExtension):
    """The e-puck swarm of ``sim``: the core's :class:`EpuckSwarm` (seeded with ``seed``), one
    robot per name of ``robot_names`` at the scene's start poses, their commands, LEDs
    (:attr:`leds`), noise (:attr:`noise`), cameras (:attr:`camera`) and model (:attr:`model`).
    Stepped before every other extension (the builder adds it first)."""

    def __init__(self, sim, seed: int, robot_names: Sequence[str] = (), noise: NoiseSettings = None,
                 cmd_timeout_s: float = CMD_TIMEOUT_S, camera: CameraSpec = None,
                 robot_namer: Callable[[int], str] = None):
        """``robot_namer`` names robot number k (suffix ``#k-1``) added later; by default
        ``ePuck<k>``, as the V-REP model's script. ``cmd_timeout_s`` 0 turns the watchdog off.
        SceneError when the robots find no place."""
        self.sim = sim
        self.seed = int(seed)
        self.cmd_timeout_s = float(cmd_timeout_s)
        self.camera = camera if camera is not None else CameraSpec()
        self.robot_namer = robot_namer if robot_namer is not None else VREP.robot_name
        self.model = default_model()
        self.swarm = EpuckSwarm(sim.world, self.model, self.seed)
        self.robots: List[RobotParts] = []
        self.robot_names: List[str] = []
        self.start_poses = []
        self._index_by_name = {}
        self._commands_lock = threading.Lock()
        self.command = RobotCommand(np.zeros((0, 2)), np.zeros(0))
        self.leds = RobotLeds()          # set by cmd_led, read by the LED face
        starts = place_robots(sim.scene, len(robot_names), self.model.body_radius_m)
        for number, (name, pose) in enumerate(zip(robot_names, starts)):
            self._add(number, name, pose)
        self.noise = noise if noise is not None else NoiseSettings()
        self.noise.apply(self.swarm, self.robot_names)
        self._refresh()

    @property
    def size(self) -> int:
        return len(self.robot_names)

    def robot_index(self, name: str) -> int:
        """Index of a robot by name; -1 when there is no such robot."""
        return self._index_by_name.get(name, -1)

    # --- robots added and removed ---------------------------------------------------------
    def add_robot(self, near_xy=(0.0, 0.0), yaw_rad: float = 0.0) -> RobotParts:
        """A new e-puck at the free place nearest ``near_xy``, named as V-REP names a pasted
        model (:func:`next_robot_number`); then the simulation's listeners are called.
        SceneError when no place is free."""
        parts = self._place(near_xy, yaw_rad)
        self.sim.objects_changed()
        return parts

    def remove_robot(self, name: str) -> List[int]:
        """Remove a robot with all its objects (through the simulation, which then calls its
        listeners); returns their handles. KeyError if unknown."""
        return self.sim.remove_object(self.robots[self._index_by_name[name]].root.handle)

    def load_model(self, model):
        """simLoadModel of an e-puck's model file: a new robot (its parts) where the file
        places it (:meth:`add_robot`); None for another robot's file."""
        if model.robot != MODEL_KIND:
            return None
        return self._place(model.position_m, model.yaw_rad)

    def _place(self, near_xy, yaw_rad) -> RobotParts:
        number = next_robot_number(o.name for o in self.sim.registry.objects())
        name = self.robot_namer(number)
        if name in self._index_by_name:
            raise ValueError(f"a robot named '{name}' exists already")
        occupied = np.vstack((self.swarm.poses[:, :2],
                              np.reshape(self.start_poses, (-1, 3))[:, :2]))
        x, y = free_place(self.sim.scene, self.sim.live_obstacles(), occupied,
                          self.model.body_radius_m, near_xy)
        parts = self._add(number, name, (x, y, float(yaw_rad)))
        self.noise.apply(self.swarm, self.robot_names)
        self._refresh()
        return parts

    def _add(self, number, name, pose) -> RobotParts:
        x, y, yaw = pose
        parts = register_epuck(self.sim.registry, self.model, number, name,
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

    def _refresh(self):
        self._poses = self.swarm.poses
        self._wheel_angles = self.swarm.wheel_angles

    # --- the simulation's hooks for the robots' objects ---------------------------------------
    def owns(self, obj) -> bool:
        return obj.robot in self._index_by_name

    def claims_removal(self, obj) -> bool:
        """A robot's base object takes the whole robot; any other part of it is refused."""
        if obj.robot not in self._index_by_name:
            return False
        if obj.part != "root":
            base = self.robots[self._index_by_name[obj.robot]].root.name
            raise ValueError(f"'{obj.name}' is part of robot {obj.robot}; remove the "
                             f"robot's base object '{base}' instead")
        return True

    def forget(self, removed: set) -> None:
        """The robots whose base object went leave their rows, the LEDs and the swarm."""
        for parts in [p for p in self.robots if p.root.handle in removed]:
            name = parts.root.robot
            index = self._index_by_name[name]
            with self._commands_lock:
                del self.robots[index], self.robot_names[index], self.start_poses[index]
                self._index_by_name = {n: i for i, n in enumerate(self.robot_names)}
                self.command = RobotCommand(np.delete(self.command.wheel_rad_s, index, axis=0),
                                            np.delete(self.command.stamp_s, index))
            self.leds.remove(name)
            self.swarm.remove_robot(index)      # its body left the world with its object
        self._refresh()

    def move_object(self, obj, position, quat):
        """A robot moves by its base object (x, y and yaw: robots stay on the ground); its
        parts are rigid (ValueError)."""
        if obj.part != "root":
            raise ValueError(f"'{obj.name}' is part of robot {obj.robot}; move the robot's "
                             "base object instead")
        i = self._index_by_name[obj.robot]
        self.swarm.set_pose(i, float(position[0]), float(position[1]), float(yaw_of(quat)))
        self._refresh()

    def object_velocity(self, obj):
        """Every part of a robot moves with it."""
        vx, vy, wz = self.swarm.velocities[self._index_by_name[obj.robot]]
        return np.array([vx, vy, 0.0]), np.array([0.0, 0.0, wz])

    # --- commands (from the ROS faces and the V-REP API) -----------------------------------------
    def set_wheel_speeds(self, name: str, left_rad_s: float, right_rad_s: float) -> bool:
        """Command a robot's wheels; non-finite values are refused (returns False). A robot
        that no longer exists ignores it."""
        if not (math.isfinite(left_rad_s) and math.isfinite(right_rad_s)):
            return False
        with self._commands_lock:
            index = self._index_by_name.get(name)
            if index is not None:
                self.command.wheel_rad_s[index] = (left_rad_s, right_rad_s)
                self.command.stamp_s[index] = self.sim.time_s
        return True

    def set_wheel_speed(self, name: str, column: int, rad_s: float):
        """One wheel's speed, as a joint command: it persists (no cmd_vel watchdog)."""
        with self._commands_lock:
            index = self._index_by_name[name]
            self.command.wheel_rad_s[index, column] = rad_s
            self.command.stamp_s[index] = np.inf

    # --- stepping ------------------------------------------------------------------------------
    def step(self, dt: float) -> None:
        """The command watchdog (against the step's start, the time commands are stamped
        with), then the swarm's step in the core: all robots' drive, contacts, IR, IMU, noise."""
        if self.cmd_timeout_s > 0.0:
            started_s = (self.sim.frame - 1) * self.sim.step_s
            stale = (started_s - self.command.stamp_s) > self.cmd_timeout_s
            self.command.wheel_rad_s[stale] = 0.0
        self.swarm.step(dt, self.command.wheel_rad_s)
        self._refresh()

    def reset(self) -> None:
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

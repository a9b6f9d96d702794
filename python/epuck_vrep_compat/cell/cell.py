"""The industrial cell inside a :class:`Simulation`: URDF robots in pybullet, the walking
operator, and the cell's sensors computed by the C++ core after the poses are updated.

One step, one way: scripts and client commands -> pybullet -> link and operator poses into the
collision world (one batched call) -> proximity rays, laser scan, blob cameras (core) -> the
arrays the ROS faces and the ``/vrep`` services read.
"""
import math
from typing import Dict, List

import numpy as np
import pybullet as pb

from epuck_vrep_compat._core import GROUP_ALL
from epuck_vrep_compat.cell.blob_signals import blob_signal_names, write_blob_signals
from epuck_vrep_compat.cell.commands import CellCommands
from epuck_vrep_compat.cell.devices.arm_recovery import checkpoint, recover_diverged
from epuck_vrep_compat.cell.devices.arm_script import scripted_motion
from epuck_vrep_compat.cell.devices.articulated import ArticulatedRobot
from epuck_vrep_compat.cell.devices.cell_sensors import add_ceiling_camera, add_kinect, add_laser
from epuck_vrep_compat.cell.devices.link_collisions import LinkCollisions
from epuck_vrep_compat.cell.devices.operator import add_operator
from epuck_vrep_compat.cell.devices.ray_proximity import RayProximityBank
from epuck_vrep_compat.cell.loaded_models import load_cell_robot
from epuck_vrep_compat.cell.speed_watchdog import SpeedScaleWatchdog
from epuck_vrep_compat.sim.extension import SimulationExtension
from epuck_vrep_compat.geometry.transforms import yaw_of


class Cell(SimulationExtension):
    """The industrial cell, as an extension of the :class:`Simulation`: it builds the cell's
    devices (arms, operator, proximity sensors, laser, ceiling cameras, Kinect) into the
    simulation's registry and collision world, steps them after the e-pucks, and answers the
    simulation's hooks for its objects (removal, moves, velocities, reset). Its noise streams
    are seeded with ``laser_seed`` and ``kinect_seed`` (the builder derives them by name)."""

    def __init__(self, sim, spec, laser_seed: int, kinect_seed: int):
        self.sim = sim
        self.spec = spec
        self.laser_seed, self.kinect_seed = int(laser_seed), int(kinect_seed)
        registry, world = sim.registry, sim.world
        self.client = pb.connect(pb.DIRECT)
        pb.setGravity(0.0, 0.0, -9.81, physicsClientId=self.client)
        pb.setTimeStep(sim.step_s / spec.substeps, physicsClientId=self.client)
        self.arms: List[ArticulatedRobot] = [ArticulatedRobot(self.client, a, registry)
                                             for a in spec.arms]
        self.arm_by_name: Dict[str, ArticulatedRobot] = {a.spec.name: a for a in self.arms}
        self._links = LinkCollisions(self.arms, registry, world)
        self.operator, self.operator_handles = None, ()
        if spec.operator is not None:
            robots = [(a.name, a.position_m[0], a.position_m[1]) for a in spec.arms]
            self.operator, self.operator_handles = add_operator(
                spec.operator, registry, world, sim.scene.arena.size_m, robots)
        self._operator_frame0 = sim.frame       # his time counts from here (start, reset)
        self.proximity = RayProximityBank(spec.proximity, registry, self._link_row)
        self._build_laser(registry, world)
        self._build_cameras()
        self._build_kinect()
        self.scan_count = 0                 # laser scans taken so far (a reader compares)
        self.blobs: Dict[str, np.ndarray] = {}
        self.watchdog = SpeedScaleWatchdog()    # off until configured (through commands)
        self.commands = CellCommands(self)      # the faces' one way in
        self._sync_world()
        self._sense()

    # the proximity sensors' arrays the tests read
    prox_handles = property(lambda self: self.proximity.handles)
    prox_rows = property(lambda self: self.proximity.rows)
    prox_distance = property(lambda self: self.proximity.distance)
    # every link primitive in the collision world (handles, stacked link rows)
    link_collisions = property(lambda self: self._links)

    # --- construction -------------------------------------------------------------------------
    def _link_row(self, link_name):
        """(arm, row among every link, stacked over the arms) of a link by name."""
        row0 = 0
        for arm in self.arms:
            if link_name in arm.link_names:
                return arm, row0 + arm.link_names.index(link_name)
            row0 += len(arm.link_names)
        raise ValueError(f"proximity sensor parent '{link_name}' is not a link of a cell robot")

    def _build_laser(self, registry, world):
        self.laser = self.spec.laser
        self.laser_ranges = None
        if self.laser is None:
            return
        self.laser_handle, self.scanner = add_laser(self.laser, registry, world,
                                                    self.laser_seed)
        self._scan_every = max(1, int(round(1.0 / (self.laser.rate_hz * self.sim.step_s))))

    def _build_cameras(self):
        self.camera_specs = self.spec.cameras
        operator = self.spec.operator.name if self.operator is not None else None
        self.cameras: List = [add_ceiling_camera(self.sim, c, operator) for c in self.camera_specs]

    def _build_kinect(self):
        self.kinect_depth = self.kinect_rgb = None
        if self.spec.kinect is not None:
            self.kinect_base, self.kinect_depth, self.kinect_rgb, self.depth_noise = add_kinect(
                self.sim, self.spec.kinect, self.kinect_seed)

    # --- stepping -----------------------------------------------------------------------------
    def step(self, dt: float):
        self.watchdog.check(self.arms, self.sim.time_s)
        saved = [checkpoint(arm) for arm in self.arms]
        for arm in self.arms:
            arm.script_time += dt * arm.speed_scale     # a safety override slows the script
            if not arm.external:
                scripted_motion(arm, arm.script_time)
            arm.move_base(dt)
            arm.apply_commands()
        for _ in range(self.spec.substeps):
            pb.stepSimulation(physicsClientId=self.client)
        for arm in self.arms:
            arm.read_state()
        problem = recover_diverged(self.arms, saved, self.sim.time_s)
        if self.operator is not None:       # his pose: a function of simulated time only
            self.operator.seek((self.sim.frame - self._operator_frame0) * self.sim.step_s)
        self._sync_world()
        self._sense()
        write_blob_signals(self.sim.signals["float"], self.camera_specs, self.blobs)
        if problem:                 # reported once the step is whole (arm_recovery)
            raise ValueError(problem)

    def link_poses(self):
        """Every link frame in the world, stacked over the robots (as of the last step)."""
        return self._positions, self._quats

    def _sync_world(self):
        positions = (np.concatenate([a.link_position for a in self.arms]) if self.arms
                     else np.zeros((0, 3)))
        quats = (np.concatenate([a.link_quat for a in self.arms]) if self.arms
                 else np.zeros((0, 4)))
        self._positions, self._quats = positions, quats
        handles, p, q = [self._links.handles], [], []
        if len(self._links.handles):
            wp, wq = self._links.world_poses(positions, quats)
            p.append(wp)
            q.append(wq)
        if self.operator is not None:
            base_p, base_q = self.operator.pose()
            body_p = base_p + (0.0, 0.0, self.operator.body_centre_z)
            head_p = base_p + (0.0, 0.0, self.operator.head_centre_z)
            handles.append(np.asarray(self.operator_handles, dtype=np.int32))
            p.append(np.stack((body_p, head_p)))
            q.append(np.stack((base_q, base_q)))
        if p:
            self.sim.world.set_poses(np.concatenate(handles), np.concatenate(p),
                                     np.concatenate(q))

    def _sense(self):
        self.proximity.sense(self.sim.world, self._positions, self._quats)
        if self.laser is not None and self.sim.frame % self._scan_every == 0:
            position, quat = self.sim.registry.world_pose(self.laser_handle)
            self.laser_ranges = self.scanner.scan(self.sim.world, position, quat,
                                                  self.laser_handle, GROUP_ALL)
            self.scan_count += 1
        for camera, c in zip(self.cameras, self.camera_specs):
            if c.blob_topics:
                self.blobs[c.name] = camera.blob_packet()

    def published_signals(self):
        """The blob cameras' float signals (:mod:`blob_signals`)."""
        return [("float", name) for name in blob_signal_names(self.camera_specs)]

    # --- objects ------------------------------------------------------------------------------
    def owns(self, obj) -> bool:
        return obj.robot in self.arm_by_name or (
            self.operator is not None and obj.handle in self.operator_handles)

    def claims_removal(self, obj) -> bool:
        """simRemoveObject/simRemoveModel on the cell: a robot's base object takes the whole
        robot (its links, joints and the proximity sensors mounted on it), the operator's body
        takes the operator, and a sensor, camera, laser or the Kinect goes alone. True for an
        object of the cell that may go (the simulation removes it with its descendants, then
        calls :meth:`forget`), False for one that is not the cell's; ValueError for a part that
        only goes with its whole."""
        if self.operator is not None and obj.handle in self.operator_handles:
            if obj.handle != self.operator_handles[0]:
                raise ValueError(f"'{obj.name}' is part of the operator; remove "
                                 f"'{self.sim.registry.get(self.operator_handles[0]).name}' "
                                 "instead")
            return True
        if obj.handle in self.proximity.handles:
            return True
        if obj.robot in self.arm_by_name:
            arm = self.arm_by_name[obj.robot]
            if obj.part != "base":
                raise ValueError(f"'{obj.name}' is part of robot {obj.robot}; remove the "
                                 f"robot's base object '{arm.objects[arm.chain.root].name}' "
                                 "instead")
            return True
        return obj.handle in self._device_handles()

    def _device_handles(self):
        handles = [c.handle for c in self.cameras]
        if self.laser is not None:
            handles.append(self.laser_handle)
        if self.spec.kinect is not None:
            handles += [v.handle for v in (self.kinect_depth, self.kinect_rgb) if v is not None]
            if self.kinect_base in self.sim.registry:
                handles.append(self.kinect_base)
        return handles

    def forget(self, removed):
        """After the simulation removed these handles: drop every part whose scene object is
        gone, re-index, and sense again."""
        for arm in [a for a in self.arms if a.objects[a.chain.root].handle in removed]:
            pb.removeBody(arm.body, physicsClientId=self.client)
            self.arms.remove(arm)
            del self.arm_by_name[arm.spec.name]
        self._links.index(self.arms)
        self.proximity.index(self.sim.registry)
        if self.operator is not None and self.operator_handles[0] in removed:
            self.operator, self.operator_handles = None, ()
        if self.laser is not None and self.laser_handle in removed:
            self.laser, self.laser_ranges = None, None
        kept = [(v, c) for v, c in zip(self.cameras, self.camera_specs) if v.handle not in removed]
        blob_topics = set(blob_signal_names(self.camera_specs))
        self.cameras = [v for v, _ in kept]
        self.camera_specs = [c for _, c in kept]
        for topic in blob_topics - set(blob_signal_names(self.camera_specs)):
            self.sim.signals["float"].pop(topic, None)      # a removed camera's signals go
        self.blobs = {c.name: self.blobs[c.name] for c in self.camera_specs
                      if c.name in self.blobs}
        if self.kinect_depth is not None and self.kinect_depth.handle in removed:
            self.kinect_depth = None
        if self.kinect_rgb is not None and self.kinect_rgb.handle in removed:
            self.kinect_rgb = None
        self._sync_world()
        self._sense()

    def move_object(self, obj, position, quat):
        """A robot's base moves (x, y, yaw; mobile or not); its links follow their joints; the
        operator follows its path."""
        if self.operator is not None and obj.handle in self.operator_handles:
            raise ValueError(f"'{obj.name}' walks its path; it cannot be placed")
        arm = self.arm_by_name[obj.robot]
        if obj.part != "base":
            raise ValueError(f"'{obj.name}' is part of robot {obj.robot}; move the robot's "
                             "base object, or its joints")
        before = arm.base_xy_yaw.copy(), arm.base_z
        arm.base_xy_yaw[:] = (float(position[0]), float(position[1]), float(yaw_of(quat)))
        arm.base_z = float(position[2])
        try:
            self._place(arm)
        except ValueError:          # the core refused a link's pose: all or nothing
            arm.base_xy_yaw[:], arm.base_z = before
            self._place(arm)
            raise

    def load_model(self, model):
        """simLoadModel of a cell robot's model file (see :mod:`loaded_models`)."""
        return load_cell_robot(self, model) if model.robot == "cell_robot" else None

    def add_arm(self, arm):
        """A robot built while the simulation runs (a model loaded): stepped from now on."""
        self.arms.append(arm)
        self.arm_by_name[arm.spec.name] = arm
        self._links.add(arm, self.sim.registry, self.sim.world)
        self._links.index(self.arms)
        self._sync_world()
        self._sense()

    def _place(self, arm):
        arm.place_base()
        arm.read_state()
        self._sync_world()
        self._sense()

    def object_velocity(self, obj):
        arm = self.arm_by_name.get(obj.robot)
        if arm is None or obj.part != "base" or not arm.spec.mobile:
            return np.zeros(3), np.zeros(3)
        vx, vy, wz = arm.twist * arm.speed_scale
        yaw = arm.base_xy_yaw[2]
        return (np.array([vx * math.cos(yaw) - vy * math.sin(yaw),
                          vx * math.sin(yaw) + vy * math.cos(yaw), 0.0]),
                np.array([0.0, 0.0, wz]))

    def reset(self):
        self.watchdog.restart(self.sim.time_s)
        for arm in self.arms:
            arm.reset()
        self._operator_frame0 = self.sim.frame
        if self.operator is not None:
            self.operator.reset()
        if self.laser is not None:
            self.scanner.reseed(self.laser_seed)
        if self.spec.kinect is not None:
            self.depth_noise.reseed(self.kinect_seed)
        self._sync_world()
        self._sense()

    def close(self):
        if pb.isConnected(self.client):
            pb.disconnect(self.client)

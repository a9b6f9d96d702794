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

from epuck_vrep_compat import _core
from epuck_vrep_compat._core import GROUP_ALL, GROUP_DYNAMIC, GROUP_ROBOT, GROUP_STATIC
from epuck_vrep_compat.cell.articulated import POSITION, ArticulatedRobot, world_poses
from epuck_vrep_compat.cell.devices import CellVision, RayProximity, pose_from_vrep_matrix
from epuck_vrep_compat.cell.operator import WalkingOperator
from epuck_vrep_compat.scene import registry as reg
from epuck_vrep_compat.scene.transforms import (
    IDENTITY_QUAT, quat_conj, quat_from_axis_angle, quat_from_rpy, yaw_of)
from epuck_vrep_compat.sim.components import _VISION_TO_CAMERA, CameraSpec

# Seeds of the cell's noise sources, offset from the simulation's seed (one stream each).
LASER_SEED_OFFSET = 0x1A5E
KINECT_SEED_OFFSET = 0x71C7
PROX_SEED_OFFSET = 0x9B0C

# V-REP vision sensors look along +z with +y up; the Kinect's body frame is x forward, z up:
# vision z = body x, vision x = body y, vision y = body z (the inverse of the vision-to-camera
# turn, since the core's camera frame is the body frame).
_BODY_TO_VISION = quat_conj(_VISION_TO_CAMERA)


class Cell:
    def __init__(self, sim, spec, seed: int):
        self.sim = sim
        self.spec = spec
        self.seed = int(seed)
        registry, world = sim.registry, sim.world
        self.client = pb.connect(pb.DIRECT)
        pb.setGravity(0.0, 0.0, -9.81, physicsClientId=self.client)
        pb.setTimeStep(sim.step_s / spec.substeps, physicsClientId=self.client)
        self.arms: List[ArticulatedRobot] = [ArticulatedRobot(self.client, a, registry)
                                             for a in spec.arms]
        self.arm_by_name: Dict[str, ArticulatedRobot] = {a.spec.name: a for a in self.arms}
        self._script_time = 0.0
        # collision primitives of every link: (arm, handle, row in the arm's links, primitive)
        self._collisions = []
        for arm in self.arms:
            for k, (row, part) in enumerate(arm.collision_parts()):
                link_obj = arm.objects[arm.link_names[row]]
                handle = self._collision_handle(registry, link_obj, k, arm.spec.name)
                self._add_primitive(world, handle, part, arm.spec.color, GROUP_ROBOT)
                self._collisions.append((arm, handle, row, part))
        self._index_collisions()
        self.operator = None
        if spec.operator is not None:
            self.operator = WalkingOperator(spec.operator)
            o = spec.operator
            base = registry.add(o.name, reg.SHAPE, reg.WORLD, pose_source=self.operator.pose,
                                properties=dict(shape="cylinder", color=o.color))
            world.add_cylinder(base.handle, o.body_radius_m, o.body_height_m, np.zeros(3),
                               IDENTITY_QUAT, o.color, GROUP_DYNAMIC)
            head = registry.add(o.name + "_head", reg.SHAPE, base.handle,
                                (0.0, 0.0, self.operator.head_centre_z),
                                properties=dict(shape="sphere", color=o.color))
            world.add_sphere(head.handle, o.head_radius_m, np.zeros(3), IDENTITY_QUAT, o.color,
                             GROUP_DYNAMIC)
            self.operator_handles = (base.handle, head.handle)
        self._build_proximity(registry)
        self._build_laser(registry, world)
        self._build_cameras(registry)
        self._build_kinect(registry, world)
        self.scan_count = 0                 # laser scans taken so far (a reader compares)
        self.blobs: Dict[str, np.ndarray] = {}
        self._sync_world()
        self._sense()

    # --- construction -------------------------------------------------------------------------
    @staticmethod
    def _collision_handle(registry, link_obj, k, robot):
        if k == 0 and "collision" not in link_obj.properties:
            link_obj.properties["collision"] = True
            return link_obj.handle
        name = f"{link_obj.name}_collision{k}"
        while registry.handle_of(name) >= 0:
            k += 1
            name = f"{link_obj.name}_collision{k}"
        return registry.add(name, reg.SHAPE, link_obj.handle, robot=robot, part=name).handle

    def _index_collisions(self):
        """The stacked arrays ``_sync_world`` reads, from the arms there are."""
        first_row, row0 = {}, 0
        for arm in self.arms:
            first_row[id(arm)] = row0
            row0 += len(arm.link_names)
        kept = [c for c in self._collisions if id(c[0]) in first_row]
        self._collisions = kept
        self._handles = np.asarray([h for _, h, _, _ in kept], dtype=np.int32)
        self._rows = np.asarray([first_row[id(a)] + r for a, _, r, _ in kept], dtype=np.intp)
        self._offset_p = np.asarray([p.position for *_, p in kept], dtype=float).reshape(-1, 3)
        self._offset_q = np.asarray([p.quat for *_, p in kept], dtype=float).reshape(-1, 4)

    @staticmethod
    def _add_primitive(world, handle, part, color, group):
        if part.shape == "box":
            world.add_box(handle, 0.5 * np.asarray(part.size), np.zeros(3), IDENTITY_QUAT,
                          color, group)
        elif part.shape == "cylinder":
            world.add_cylinder(handle, part.size[0], part.size[1], np.zeros(3), IDENTITY_QUAT,
                               color, group)
        else:
            world.add_sphere(handle, part.size[0], np.zeros(3), IDENTITY_QUAT, color, group)

    def _link_row(self, link_name):
        row0 = 0
        for arm in self.arms:
            if link_name in arm.link_names:
                return arm, row0 + arm.link_names.index(link_name)
            row0 += len(arm.link_names)
        raise ValueError(f"proximity sensor parent '{link_name}' is not a link of a cell robot")

    def _build_proximity(self, registry):
        self._prox = []                          # (spec, scene object, component)
        for p in self.spec.proximity:
            arm, _ = self._link_row(p.parent)
            quat = quat_from_rpy(*p.rpy_rad)
            obj = registry.add(p.name, reg.PROXIMITY_SENSOR, arm.objects[p.parent].handle,
                               p.position_m, quat, robot=arm.spec.name, part=p.name)
            component = RayProximity(self, len(self._prox))
            obj.properties["proximity"] = component
            obj.properties["range_m"] = (p.min_range_m, p.max_range_m)
            self._prox.append((p, obj, component))
        self._index_proximity()

    def _index_proximity(self):
        """The core's ray array and its per-sensor arrays, from the sensors there are."""
        registry = self.sim.registry
        self._prox = [entry for entry in self._prox if entry[1].handle in registry]
        specs = [p for p, _, _ in self._prox]
        n = len(specs)
        self.prox_rows = np.zeros(n, dtype=np.intp)
        self.prox_offset_p = np.zeros((n, 3))
        self.prox_offset_q = np.tile(IDENTITY_QUAT, (n, 1))
        for i, (p, _, component) in enumerate(self._prox):
            self.prox_rows[i] = self._link_row(p.parent)[1]
            self.prox_offset_p[i] = p.position_m
            self.prox_offset_q[i] = quat_from_rpy(*p.rpy_rad)
            component._index = i
        self.prox_handles = [obj.handle for _, obj, _ in self._prox]
        self.prox_sensors = _core.RayProximityArray(
            np.array([p.min_range_m for p in specs]), np.array([p.max_range_m for p in specs]))
        self.prox_state = np.zeros(n, dtype=np.int32)
        self.prox_distance = np.full(n, np.inf)
        self.prox_point = np.zeros((n, 3))
        self.prox_handle = np.full(n, -1, dtype=np.int32)
        self.prox_normal = np.zeros((n, 3))

    def _build_laser(self, registry, world):
        self.laser = self.spec.laser
        self.laser_ranges = None
        if self.laser is None:
            return
        s = self.laser
        obj = registry.add(s.name, reg.SHAPE, reg.WORLD, s.position_m,
                           quat_from_axis_angle((0, 0, 1), s.yaw_rad),
                           properties=dict(shape="box", color=(0.1, 0.1, 0.1)))
        # the scanner's housing (50 x 50 x 70 mm) around the scan origin; the scan ignores it
        world.add_box(obj.handle, np.array([0.025, 0.025, 0.035]), np.asarray(s.position_m),
                      obj.local_quat, (0.1, 0.1, 0.1), GROUP_STATIC)
        self.laser_handle = obj.handle
        self.scanner = _core.LaserScanner(s.angle_min_rad, s.angle_increment_rad, s.count,
                                          s.range_min_m, s.range_max_m, s.noise_sigma_m,
                                          s.noise_relative, self.seed + LASER_SEED_OFFSET)
        self._scan_every = max(1, int(round(1.0 / (s.rate_hz * self.sim.step_s))))

    def _build_cameras(self, registry):
        self.cameras: List[CellVision] = []
        self.camera_specs = self.spec.cameras
        for c in self.spec.cameras:
            position, quat = pose_from_vrep_matrix(c.matrix)
            obj = registry.add(c.name, reg.VISION_SENSOR, reg.WORLD, position, quat)
            w, h = c.resolution
            # V-REP's perspective angle spans the larger image side
            half = math.tan(0.5 * c.angle_rad) * (h / max(w, h))
            spec = CameraSpec(width=w, height=h, rate_hz=1.0 / self.sim.step_s,
                              vertical_fov_rad=2.0 * math.atan(half), near_m=c.near_m,
                              far_m=c.far_m)
            mask = GROUP_ALL
            if c.render is not None:
                if self.operator is None or c.render != self.spec.operator.name:
                    raise ValueError(f"camera '{c.name}': render entity '{c.render}' must be "
                                     "the operator")
                mask = GROUP_DYNAMIC
            vision = CellVision(self.sim, obj.handle, spec, mask=mask,
                                blob=bool(c.blob_topics))
            obj.properties["vision"] = vision
            self.cameras.append(vision)

    def _build_kinect(self, registry, world):
        k = self.spec.kinect
        self.kinect_depth = self.kinect_rgb = None
        if k is None:
            return
        base = registry.add(k.name, reg.SHAPE, reg.WORLD, k.position_m, quat_from_rpy(*k.rpy_rad),
                            properties=dict(shape="box", color=(0.15, 0.15, 0.15)))
        self.kinect_base = base.handle
        w, h = k.resolution
        vfov = 2.0 * math.atan(math.tan(0.5 * k.horizontal_fov_rad) * h / w)
        spec = CameraSpec(width=w, height=h, rate_hz=30.0, vertical_fov_rad=vfov, near_m=k.near_m,
                          far_m=k.far_m)
        self.depth_noise = _core.DepthNoise(seed=self.seed + KINECT_SEED_OFFSET)
        for suffix, offset_y, noise in (("_depth", -0.0125, self.depth_noise),
                                        ("_rgb", 0.0125, None)):
            obj = registry.add(k.name + suffix, reg.VISION_SENSOR, base.handle,
                               (0.0, offset_y, 0.0), _BODY_TO_VISION)
            vision = CellVision(self.sim, obj.handle, spec, depth_noise=noise)
            obj.properties["vision"] = vision
            if noise is None:
                self.kinect_rgb = vision
            else:
                self.kinect_depth = vision

    # --- stepping -----------------------------------------------------------------------------
    def step(self, dt: float):
        self._script_time += dt
        for arm in self.arms:
            if not arm.external:
                self._script(arm, self._script_time)
            arm.move_base(dt)
            arm.apply_commands()
        for _ in range(self.spec.substeps):
            pb.stepSimulation(physicsClientId=self.client)
        for arm in self.arms:
            arm.read_state()
        if self.operator is not None:
            self.operator.advance(dt)
        self._sync_world()
        self._sense()
        self._write_blob_signals()

    def _script(self, arm, t):
        """Default motions, as the thesis's child scripts: each joint swings sinusoidally about
        the middle of its range (phase-shifted per joint); a mobile base drives a square."""
        s = arm.spec
        if s.script == "none":
            return
        w = 2.0 * math.pi / s.script_period_s
        for k, joint in enumerate(arm.joints):
            if joint.cyclic:
                continue
            lower, upper = joint.lower, joint.upper
            if joint.prismatic:
                centre, half = 0.5 * (lower + upper), 0.5 * (upper - lower)
            else:
                centre = min(max(0.0, lower), upper)
                half = min(centre - lower, upper - centre)
                if half < 0.1 * (upper - lower):      # zero at a stop (youBot): mid-range
                    centre, half = 0.5 * (lower + upper), 0.5 * (upper - lower)
            arm.command(k, POSITION, centre + s.script_amplitude * half *
                        math.sin(w * t + 0.7 * k), external=False)
        if s.mobile and s.script == "square":
            side = int(t / (0.25 * s.script_period_s)) % 4
            speed = 0.15
            arm.set_twist(*((speed, 0, 0), (0, speed, 0), (-speed, 0, 0), (0, -speed, 0))[side],
                          external=False)

    def link_poses(self):
        """Every link frame in the world, stacked over the robots (as of the last step)."""
        return self._positions, self._quats

    def _sync_world(self):
        positions = (np.concatenate([a.link_position for a in self.arms]) if self.arms
                     else np.zeros((0, 3)))
        quats = (np.concatenate([a.link_quat for a in self.arms]) if self.arms
                 else np.zeros((0, 4)))
        self._positions, self._quats = positions, quats
        handles, p, q = [self._handles], [], []
        if len(self._handles):
            wp, wq = world_poses(positions, quats, self._rows, self._offset_p, self._offset_q)
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
        if len(self.prox_rows):
            sp, sq = world_poses(self._positions, self._quats, self.prox_rows,
                                 self.prox_offset_p, self.prox_offset_q)
            (self.prox_state, self.prox_distance, self.prox_point, self.prox_handle,
             self.prox_normal) = self.prox_sensors.read(self.sim.world, sp, sq, -1, GROUP_ALL)
        if self.laser is not None and self.sim.frame % self._scan_every == 0:
            position, quat = self.sim.registry.world_pose(self.laser_handle)
            self.laser_ranges = self.scanner.scan(self.sim.world, position, quat,
                                                  self.laser_handle, GROUP_ALL)
            self.scan_count += 1
        for camera, c in zip(self.cameras, self.camera_specs):
            if c.blob_topics:
                self.blobs[c.name] = camera.blob_packet()

    def _write_blob_signals(self):
        """The thesis's child script, each step: a blob camera's first blob x and y become the
        float signals of its ``blob_topics``, which are cleared while it sees no blob."""
        floats = self.sim.signals["float"]
        for c in self.camera_specs:
            if not c.blob_topics:
                continue
            packet = self.blobs.get(c.name)
            x_topic, y_topic = c.blob_topics
            if packet is not None and len(packet) > 6 and packet[0] >= 1:
                floats[x_topic] = float(packet[4])
                floats[y_topic] = float(packet[5])
            else:
                floats.pop(x_topic, None)
                floats.pop(y_topic, None)

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
        if obj.handle in self.prox_handles:
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
        self._index_collisions()
        self._index_proximity()
        if self.operator is not None and self.operator_handles[0] in removed:
            self.operator, self.operator_handles = None, ()
        if self.laser is not None and self.laser_handle in removed:
            self.laser, self.laser_ranges = None, None
        kept = [(v, c) for v, c in zip(self.cameras, self.camera_specs) if v.handle not in removed]
        blob_topics = {t for c in self.camera_specs for t in c.blob_topics}
        self.cameras = [v for v, _ in kept]
        self.camera_specs = [c for _, c in kept]
        for topic in blob_topics - {t for c in self.camera_specs for t in c.blob_topics}:
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

    def _place(self, arm):
        arm.place_base()
        arm.read_state()
        self._sync_world()
        self._sense()

    def object_velocity(self, obj):
        arm = self.arm_by_name.get(obj.robot)
        if arm is None or obj.part != "base" or not arm.spec.mobile:
            return np.zeros(3), np.zeros(3)
        vx, vy, wz = arm.twist
        yaw = arm.base_xy_yaw[2]
        return (np.array([vx * math.cos(yaw) - vy * math.sin(yaw),
                          vx * math.sin(yaw) + vy * math.cos(yaw), 0.0]),
                np.array([0.0, 0.0, wz]))

    def reset(self):
        for arm in self.arms:
            arm.reset()
        if self.operator is not None:
            self.operator.reset()
        self._script_time = 0.0
        if self.laser is not None:
            self.scanner.reseed(self.seed + LASER_SEED_OFFSET)
        if self.spec.kinect is not None:
            self.depth_noise.reseed(self.seed + KINECT_SEED_OFFSET)
        self._sync_world()
        self._sense()

    def close(self):
        if pb.isConnected(self.client):
            pb.disconnect(self.client)

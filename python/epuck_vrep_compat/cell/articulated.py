"""Articulated robots from URDF, simulated by pybullet, registered as V-REP-style objects.

pybullet (DIRECT, no GUI) integrates the joints under motor control; our scene registry holds one
object per link (a shape) and per movable joint, named as in the URDF, in V-REP's hierarchy:
base shape -> joint -> link shape -> joint -> ... A joint object's frame has its z axis along
the joint axis (V-REP's convention) and does not move with the joint; the link below it does.
Each link's collision primitives (box, cylinder, sphere) are mirrored into the core's collision
world so the ray-cast sensors see the robot.

Commands (target position or velocity, maximum force) are stored by the joint components and
sent to pybullet at the start of the next step: data flows one way per step.
"""
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np
import pybullet as pb

from epuck_vrep_compat.scene import registry as reg
from epuck_vrep_compat.scene.transforms import (
    IDENTITY_QUAT, compose, inverse, quat_from_axis_angle, quat_from_rpy, quat_from_yaw,
    quat_mul, quat_rotate)
from epuck_vrep_compat.sim.components import ComponentError, wrap_angle
from epuck_vrep_compat.vrep import constants as vc

POSITION = "position"
VELOCITY = "velocity"
# youBot mecanum base: wheel radius and half wheel base + half track (models.md 4.1)
WHEELS = ("fl", "rl", "rr", "fr")
WHEEL_RADIUS_M = 0.0475
WHEEL_LX_PLUS_LY_M = 0.228 + 0.158


@dataclass
class Collision:
    shape: str                   # box | cylinder | sphere
    size: tuple                  # box: full extents; cylinder: (radius, length); sphere: (r,)
    position: np.ndarray
    quat: np.ndarray


@dataclass
class UrdfJoint:
    name: str
    kind: str                    # revolute | continuous | prismatic | fixed
    parent: str
    child: str
    position: np.ndarray
    quat: np.ndarray
    axis: np.ndarray
    lower: float = -math.pi
    upper: float = math.pi
    velocity: float = 1.0
    effort: float = 100.0


@dataclass
class UrdfModel:
    root: str
    joints: List[UrdfJoint]
    collisions: Dict[str, List[Collision]] = field(default_factory=dict)


def _origin(element):
    o = element.find("origin") if element is not None else None
    if o is None:
        return np.zeros(3), IDENTITY_QUAT.copy()
    xyz = np.array([float(v) for v in o.get("xyz", "0 0 0").split()])
    rpy = [float(v) for v in o.get("rpy", "0 0 0").split()]
    return xyz, quat_from_rpy(*rpy)


def parse_urdf(path: str) -> UrdfModel:
    """The parts of a URDF the cell needs: joints in file order and collision primitives."""
    root = ET.parse(path).getroot()
    collisions = {}
    for link in root.findall("link"):
        shapes = []
        for c in link.findall("collision"):
            geometry = c.find("geometry")
            position, quat = _origin(c)
            box, cyl, sph = (geometry.find(k) for k in ("box", "cylinder", "sphere"))
            if box is not None:
                shapes.append(Collision("box", tuple(float(v) for v in box.get("size").split()),
                                        position, quat))
            elif cyl is not None:
                shapes.append(Collision("cylinder", (float(cyl.get("radius")),
                                                     float(cyl.get("length"))), position, quat))
            elif sph is not None:
                shapes.append(Collision("sphere", (float(sph.get("radius")),), position, quat))
            else:
                raise ValueError(f"{path}: link '{link.get('name')}' has a collision geometry "
                                 "other than box, cylinder or sphere")
        collisions[link.get("name")] = shapes
    joints = []
    for j in root.findall("joint"):
        position, quat = _origin(j)
        axis = j.find("axis")
        limit = j.find("limit")
        joint = UrdfJoint(j.get("name"), j.get("type"), j.find("parent").get("link"),
                          j.find("child").get("link"), position, quat,
                          np.array([float(v) for v in axis.get("xyz").split()])
                          if axis is not None else np.array([1.0, 0.0, 0.0]))
        if limit is not None:
            joint.lower = float(limit.get("lower", joint.lower))
            joint.upper = float(limit.get("upper", joint.upper))
            joint.velocity = float(limit.get("velocity", joint.velocity))
            # an explicit effort of 0 marks a passive joint (no motor), e.g. a mecanum roller
            joint.effort = float(limit.get("effort", joint.effort))
        joints.append(joint)
    children = {j.child for j in joints}
    roots = [name for name in collisions if name not in children]
    if len(roots) != 1:
        raise ValueError(f"{path}: expected one root link, found {roots}")
    return UrdfModel(roots[0], joints, collisions)


def _z_to_axis(axis):
    """Rotation taking +z onto ``axis`` (V-REP joints act about their own z)."""
    axis = axis / np.linalg.norm(axis)
    z = np.array([0.0, 0.0, 1.0])
    c = float(np.dot(z, axis))
    if c > 1.0 - 1e-12:
        return IDENTITY_QUAT.copy()
    if c < -1.0 + 1e-12:
        return quat_from_axis_angle((1.0, 0.0, 0.0), math.pi)
    return quat_from_axis_angle(np.cross(z, axis), math.acos(c))


class ArmJoint:
    """A movable joint of an articulated robot (V-REP: motor enabled, position control)."""

    mode = vc.JOINTMODE_FORCE

    def __init__(self, robot, index: int, urdf: UrdfJoint):
        self._robot = robot
        self.index = index                     # among the robot's movable joints
        self.urdf = urdf
        self.cyclic = urdf.kind == "continuous"
        self.joint_type = vc.JOINT_PRISMATIC if urdf.kind == "prismatic" else vc.JOINT_REVOLUTE
        self.range_min = -math.pi if self.cyclic else urdf.lower
        self.range_span = -1.0 if self.cyclic else urdf.upper - urdf.lower
        self.max_force = urdf.effort

    def position(self) -> float:
        q = float(self._robot.q[self.index])
        return wrap_angle(q) if self.cyclic else q

    def velocity(self) -> float:
        return float(self._robot.qd[self.index])

    def effort(self) -> float:
        return float(self._robot.tau[self.index])

    def _finite(self, what, value):
        if not math.isfinite(value):
            raise ComponentError(f"{what} {value} is not finite")

    def _clamped(self, value):
        return value if self.cyclic else min(max(value, self.urdf.lower), self.urdf.upper)

    def set_target_position(self, value: float):
        self._finite("target position", value)
        self._robot.command(self.index, POSITION, self._clamped(value))

    def set_target_velocity(self, value: float):
        self._finite("target velocity", value)
        self._robot.command(self.index, VELOCITY, value)

    def set_position(self, value: float):
        self._finite("position", value)
        self._robot.reset_joint(self.index, self._clamped(value))

    def set_force(self, value: float):
        self._finite("force", value)
        if value < 0.0:
            raise ComponentError(f"force {value} is negative")
        self.max_force = value
        self._robot.dirty[self.index] = True


class ArticulatedRobot:
    """One URDF robot in pybullet and in the scene registry (base object named ``spec.name``)."""

    def __init__(self, client: int, spec, registry: reg.SceneRegistry):
        self.client = client
        self.spec = spec
        self.model = parse_urdf(spec.urdf)
        self.base_xy_yaw = np.array([spec.position_m[0], spec.position_m[1], spec.yaw_rad])
        self.base_z = float(spec.position_m[2])
        self.twist = np.zeros(3)               # body-frame vx, vy, wz (mobile bases)
        self.external = False                  # a client commanded it: the script stops
        position, quat = self.base_pose()
        self.body = pb.loadURDF(spec.urdf, position.tolist(), quat.tolist(), useFixedBase=True,
                                flags=pb.URDF_USE_INERTIA_FROM_FILE
                                | pb.URDF_USE_IMPLICIT_CYLINDER, physicsClientId=client)
        self._inertial = pb.getDynamicsInfo(self.body, -1, physicsClientId=client)[3:5]
        info = [pb.getJointInfo(self.body, j, physicsClientId=client)
                for j in range(pb.getNumJoints(self.body, physicsClientId=client))]
        self._bullet_index = {i[1].decode(): i[0] for i in info}
        self._link_index = {i[12].decode(): i[0] for i in info}
        self._link_index[self.model.root] = -1
        movable = [j for j in self.model.joints if j.kind != "fixed"]
        n = len(movable)
        self.q, self.qd, self.tau = np.zeros(n), np.zeros(n), np.zeros(n)
        self.mode = [POSITION] * n
        self.target = np.zeros(n)
        self.dirty = [True] * n
        self.joint_bullet = [self._bullet_index[j.name] for j in movable]
        self.joints: List[ArmJoint] = []
        self.objects: Dict[str, reg.SceneObject] = {}
        self._register(registry, movable)
        # mecanum wheels (youBot): driven from the base's twist
        self.wheels = {w: self.movable_index(f"rollingJoint_{w}") for w in WHEELS}
        self.wheels = {w: k for w, k in self.wheels.items() if k is not None}
        # link frames in the world, refreshed every step (index = pybullet link index + 1)
        self.link_names = [self.model.root] + [i[12].decode() for i in info]
        self.link_position = np.zeros((len(self.link_names), 3))
        self.link_quat = np.tile(IDENTITY_QUAT, (len(self.link_names), 1))
        self.read_state()

    # --- registry ---------------------------------------------------------------------------
    def _register(self, registry, movable):
        base = registry.add(self.spec.name, reg.SHAPE, reg.WORLD, robot=self.spec.name,
                            part="base", pose_source=self.base_pose)
        self.objects[self.model.root] = base
        movable_index = {j.name: k for k, j in enumerate(movable)}
        for j in self.model.joints:
            parent = self.objects[j.parent]
            if j.kind == "fixed":
                self.objects[j.child] = registry.add(
                    j.child, reg.SHAPE, parent.handle, j.position, j.quat, robot=self.spec.name,
                    part=j.child)
                continue
            align = _z_to_axis(j.axis)
            k = movable_index[j.name]
            joint_obj = registry.add(j.name, reg.JOINT, parent.handle, j.position,
                                     quat_mul(j.quat, align), robot=self.spec.name, part=j.name)
            component = ArmJoint(self, k, j)
            joint_obj.properties["joint"] = component
            self.joints.append(component)
            self.objects[j.child] = registry.add(
                j.child, reg.SHAPE, joint_obj.handle, robot=self.spec.name, part=j.child,
                pose_source=self._link_pose_source(k, j.kind == "prismatic", align))

    def _link_pose_source(self, k, prismatic, align):
        back = inverse(np.zeros(3), align)[1]

        def pose():
            q = float(self.q[k])
            if prismatic:
                return np.array([0.0, 0.0, q]), back
            return np.zeros(3), quat_mul(quat_from_axis_angle((0.0, 0.0, 1.0), q), back)
        return pose

    def base_pose(self):
        x, y, yaw = self.base_xy_yaw
        return np.array([x, y, self.base_z]), quat_from_yaw(yaw)

    # --- commands ---------------------------------------------------------------------------
    def command(self, k: int, mode: str, value: float, external: bool = True):
        if self.mode[k] != mode or self.target[k] != value:
            self.mode[k], self.target[k] = mode, value
            self.dirty[k] = True
        self.external = self.external or external

    def reset_joint(self, k: int, value: float):
        pb.resetJointState(self.body, self.joint_bullet[k], value, 0.0,
                           physicsClientId=self.client)
        self.command(k, POSITION, value)
        self.read_state()

    def set_twist(self, vx: float, vy: float, wz: float, external: bool = True):
        self.twist[:] = (vx, vy, wz)
        self.external = self.external or external

    def apply_commands(self):
        for k, joint in enumerate(self.joints):
            if not self.dirty[k]:
                continue
            self.dirty[k] = False
            index, force = self.joint_bullet[k], joint.max_force
            if self.mode[k] == POSITION:
                pb.setJointMotorControl2(self.body, index, pb.POSITION_CONTROL,
                                         targetPosition=float(self.target[k]), force=force,
                                         maxVelocity=joint.urdf.velocity,
                                         physicsClientId=self.client)
            else:
                limit = joint.urdf.velocity
                velocity = min(max(float(self.target[k]), -limit), limit)
                pb.setJointMotorControl2(self.body, index, pb.VELOCITY_CONTROL,
                                         targetVelocity=velocity, force=force,
                                         physicsClientId=self.client)

    def move_base(self, dt: float):
        """Mobile bases move kinematically by their body-frame twist; mecanum wheels turn to
        match (inverse kinematics of a 4-wheel mecanum base)."""
        if not self.spec.mobile:
            return
        vx, vy, wz = self.twist
        spin = WHEEL_LX_PLUS_LY_M * wz
        speeds = {"fl": vx - vy - spin, "rl": vx + vy - spin, "rr": vx - vy + spin,
                  "fr": vx + vy + spin}
        for w, k in self.wheels.items():
            self.command(k, VELOCITY, speeds[w] / WHEEL_RADIUS_M, external=False)
        if not self.twist.any():
            return
        x, y, yaw = self.base_xy_yaw
        mid = yaw + 0.5 * wz * dt
        self.base_xy_yaw[:] = (x + (vx * math.cos(mid) - vy * math.sin(mid)) * dt,
                               y + (vx * math.sin(mid) + vy * math.cos(mid)) * dt,
                               math.atan2(math.sin(yaw + wz * dt), math.cos(yaw + wz * dt)))
        self.place_base()

    def place_base(self):
        position, quat = self.base_pose()
        com_position, com_quat = compose(position, quat, np.asarray(self._inertial[0]),
                                         np.asarray(self._inertial[1]))
        pb.resetBasePositionAndOrientation(self.body, com_position.tolist(), com_quat.tolist(),
                                           physicsClientId=self.client)

    def read_state(self):
        states = pb.getJointStates(self.body, self.joint_bullet, physicsClientId=self.client)
        for k, s in enumerate(states):
            self.q[k], self.qd[k], self.tau[k] = s[0], s[1], s[3]
        n = len(self.link_names) - 1
        if n:
            links = pb.getLinkStates(self.body, list(range(n)), computeForwardKinematics=1,
                                     physicsClientId=self.client)
            self.link_position[1:] = [s[4] for s in links]
            self.link_quat[1:] = [s[5] for s in links]
        self.link_position[0], self.link_quat[0] = self.base_pose()

    def reset(self):
        """Joints to zero (inside their limits), base to its start pose, script back on."""
        self.base_xy_yaw[:] = (self.spec.position_m[0], self.spec.position_m[1],
                               self.spec.yaw_rad)
        self.place_base()
        self.twist[:] = 0.0
        self.external = False
        for k, joint in enumerate(self.joints):
            home = joint._clamped(0.0)
            pb.resetJointState(self.body, self.joint_bullet[k], home, 0.0,
                               physicsClientId=self.client)
            self.command(k, POSITION, home, external=False)
        self.external = False
        self.read_state()

    # --- collision primitives -----------------------------------------------------------------
    def collision_parts(self):
        """[(link row, Collision)] for every primitive of every link."""
        rows = {name: i for i, name in enumerate(self.link_names)}
        return [(rows[link], c) for link, shapes in self.model.collisions.items()
                for c in shapes]

    def joint_names(self) -> List[str]:
        return [j.urdf.name for j in self.joints]

    def movable_index(self, name: str) -> Optional[int]:
        for k, j in enumerate(self.joints):
            if j.urdf.name == name:
                return k
        return None


def world_poses(link_position, link_quat, rows, offsets_position, offsets_quat):
    """Vectorised link_world[rows] * offset."""
    q = link_quat[rows]
    return link_position[rows] + quat_rotate(q, offsets_position), quat_mul(q, offsets_quat)


__all__ = ["ArmJoint", "ArticulatedRobot", "Collision", "UrdfJoint", "UrdfModel",
           "parse_urdf", "world_poses"]

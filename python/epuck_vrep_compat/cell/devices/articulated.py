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
from typing import Dict, List, Optional

import numpy as np
import pybullet as pb

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.cell.devices.arm_joint import POSITION, VELOCITY, ArmJoint
from epuck_vrep_compat.cell.devices.link_collisions import Collision, parse_collisions
from epuck_vrep_compat.cell.devices.mecanum import (
    MAX_WHEEL_SPEED_M_S, WHEEL_LX_PLUS_LY_M, WHEELS, body_twist, wheel_speeds)
from epuck_vrep_compat.geometry.transforms import (
    IDENTITY_QUAT, compose, inverse, quat_from_axis_angle, quat_from_yaw, quat_mul, quat_rotate)
from epuck_vrep_compat.geometry.urdf_kinematics import load_urdf_chain
from epuck_vrep_compat.scene import registry as reg


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


class ArticulatedRobot:
    """One URDF robot in pybullet and in the scene registry (base object named ``spec.name``;
    its joints and links by their URDF names plus ``suffix``, as V-REP names a copy's)."""

    def __init__(self, client: int, spec, registry: reg.SceneRegistry, suffix: str = ""):
        self.client = client
        self.spec = spec
        self.suffix = suffix
        self.chain = load_urdf_chain(spec.urdf)
        self.collisions = parse_collisions(spec.urdf)
        self.base_xy_yaw = np.array([spec.position_m[0], spec.position_m[1], spec.yaw_rad])
        self.base_z = float(spec.position_m[2])
        self.twist = np.zeros(3)               # body-frame vx, vy, wz (mobile bases)
        self.external = False                  # a client commanded it: the script stops
        self.wheel_driven = False              # the base follows its wheels, not its twist
        self.speed_scale = 1.0                 # a safety supervisor's override, 0..1
        self.script_time = 0.0                 # the script's clock, slowed by the scale
        position, quat = self.base_pose()
        self.body = pb.loadURDF(spec.urdf, position.tolist(), quat.tolist(), useFixedBase=True,
                                flags=pb.URDF_USE_INERTIA_FROM_FILE
                                | pb.URDF_USE_IMPLICIT_CYLINDER, physicsClientId=client)
        self._inertial = pb.getDynamicsInfo(self.body, -1, physicsClientId=client)[3:5]
        info = [pb.getJointInfo(self.body, j, physicsClientId=client)
                for j in range(pb.getNumJoints(self.body, physicsClientId=client))]
        self._bullet_index = {i[1].decode(): i[0] for i in info}
        self._link_index = {i[12].decode(): i[0] for i in info}
        self._link_index[self.chain.root] = -1
        movable = [j for j in self.chain.joints if j.joint_type != "fixed"]
        n = len(movable)
        self.q, self.qd, self.tau = np.zeros(n), np.zeros(n), np.zeros(n)
        self.mode = [POSITION] * n
        self.target = np.zeros(n)
        self.dirty = [True] * n
        self.joint_bullet = [self._bullet_index[j.name] for j in movable]
        self.joints: List[ArmJoint] = []
        self.objects: Dict[str, reg.SceneObject] = {}
        self._register(registry, movable)
        # mecanum wheels (youBot): driven from the base's twist, or driving it
        self.wheels = {w: self.movable_index(f"rollingJoint_{w}") for w in WHEELS}
        self.wheels = {w: k for w, k in self.wheels.items() if k is not None}
        # link frames in the world, refreshed every step (index = pybullet link index + 1)
        self.link_names = [self.chain.root] + [i[12].decode() for i in info]
        self.link_position = np.zeros((len(self.link_names), 3))
        self.link_quat = np.tile(IDENTITY_QUAT, (len(self.link_names), 1))
        self.read_state()

    # --- registry ---------------------------------------------------------------------------
    def _register(self, registry, movable):
        base = registry.add(self.spec.name, vc.OBJECT_SHAPE, vc.WORLD, robot=self.spec.name,
                            part="base", pose_source=self.base_pose)
        self.objects[self.chain.root] = base
        movable_index = {j.name: k for k, j in enumerate(movable)}
        for j in self.chain.joints:
            parent = self.objects[j.parent]
            if j.joint_type == "fixed":
                self.objects[j.child] = registry.add(
                    j.child + self.suffix, vc.OBJECT_SHAPE, parent.handle, j.origin_position,
                    j.origin_quat, robot=self.spec.name, part=j.child)
                continue
            align = _z_to_axis(j.axis)
            k = movable_index[j.name]
            joint_obj = registry.add(j.name + self.suffix, vc.OBJECT_JOINT, parent.handle,
                                     j.origin_position, quat_mul(j.origin_quat, align),
                                     robot=self.spec.name, part=j.name)
            component = ArmJoint(self, k, j)
            joint_obj.properties["joint"] = component
            self.joints.append(component)
            self.objects[j.child] = registry.add(
                j.child + self.suffix, vc.OBJECT_SHAPE, joint_obj.handle, robot=self.spec.name,
                part=j.child, pose_source=self._link_pose_source(k, component.prismatic, align))

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
        """A joint's command; a client's command on a mecanum wheel hands the base to the
        wheels (as V-REP's youBot is driven), until the next twist command."""
        if self.mode[k] != mode or self.target[k] != value:
            self.mode[k], self.target[k] = mode, value
            self.dirty[k] = True
        self.external = self.external or external
        if external and self.spec.mobile and k in self.wheels.values():
            self.wheel_driven = True

    def reset_joint(self, k: int, value: float):
        pb.resetJointState(self.body, self.joint_bullet[k], value, 0.0,
                           physicsClientId=self.client)
        self.command(k, POSITION, value)
        self.read_state()

    def set_twist(self, vx: float, vy: float, wz: float, external: bool = True):
        """Returns the twist applied: scaled down, direction kept, so that no mecanum wheel
        runs faster than the base's top speed (youBot: about 0.8 m/s)."""
        spin = WHEEL_LX_PLUS_LY_M * wz
        fastest = max(abs(vx) + abs(vy) + abs(spin), 1e-300)
        scale = min(1.0, MAX_WHEEL_SPEED_M_S / fastest)
        self.twist[:] = (vx * scale, vy * scale, wz * scale)
        self.external = self.external or external
        self.wheel_driven = False
        return tuple(float(v) for v in self.twist)

    def set_speed_scale(self, scale: float):
        """A safety override of every motion of the robot (script, position and velocity
        commands, the base): speeds times ``scale``, clamped to [0, 1]; 0 holds every joint
        where it is (a protective stop) until the scale rises again."""
        scale = min(max(float(scale), 0.0), 1.0)
        if scale != self.speed_scale:
            self.speed_scale = scale
            self.dirty = [True] * len(self.dirty)

    def apply_commands(self):
        scale = self.speed_scale
        for k, joint in enumerate(self.joints):
            if not self.dirty[k]:
                continue
            self.dirty[k] = False
            index, force = self.joint_bullet[k], joint.max_force
            if scale == 0.0:        # pybullet reads maxVelocity 0 as "no limit": hold instead
                pb.setJointMotorControl2(self.body, index, pb.VELOCITY_CONTROL,
                                         targetVelocity=0.0, force=force,
                                         physicsClientId=self.client)
            elif self.mode[k] == POSITION:
                pb.setJointMotorControl2(self.body, index, pb.POSITION_CONTROL,
                                         targetPosition=float(self.target[k]), force=force,
                                         maxVelocity=joint.max_velocity * scale,
                                         physicsClientId=self.client)
            else:
                limit = joint.max_velocity
                velocity = min(max(float(self.target[k]), -limit), limit) * scale
                pb.setJointMotorControl2(self.body, index, pb.VELOCITY_CONTROL,
                                         targetVelocity=velocity, force=force,
                                         physicsClientId=self.client)

    def move_base(self, dt: float):
        """Mobile bases move kinematically by their body-frame twist, and the mecanum wheels
        turn to match; or, once a client drove the wheels, the twist is the wheels' (forward
        kinematics of their velocity targets, or of their speeds under position control)."""
        if not self.spec.mobile:
            return
        if self.wheel_driven and len(self.wheels) == len(WHEELS):
            self.twist[:] = body_twist({w: self.target[k] if self.mode[k] == VELOCITY
                                        else self.qd[k] for w, k in self.wheels.items()})
        else:
            for w, omega in wheel_speeds(*self.twist).items():
                if w in self.wheels:
                    self.command(self.wheels[w], VELOCITY, omega, external=False)
        vx, vy, wz = self.twist * self.speed_scale
        if not (vx or vy or wz):
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
        """Joints to zero (inside their limits) at rest with their URDF forces, base to its
        start pose, script back on at full speed (no safety override)."""
        self.external = False
        self.script_time = 0.0
        self.speed_scale = 1.0
        for joint in self.joints:
            joint.max_force = joint.rated_force     # a client's simSetJointForce ends here
        self.hold_at((self.spec.position_m[0], self.spec.position_m[1], self.spec.yaw_rad),
                     self.spec.position_m[2], [joint._clamped(0.0) for joint in self.joints])

    def hold_at(self, base_xy_yaw, base_z: float, q):
        """At rest where it is put: the base at (x, y, yaw) and ``base_z``, driven by neither
        a twist nor its wheels, every joint at ``q`` and holding it; the state read back."""
        self.base_xy_yaw[:], self.base_z = base_xy_yaw, float(base_z)
        self.place_base()
        self.twist[:] = 0.0
        self.wheel_driven = False
        for k, value in enumerate(q):
            pb.resetJointState(self.body, self.joint_bullet[k], float(value), 0.0,
                               physicsClientId=self.client)
            self.command(k, POSITION, float(value), external=False)
        self.dirty = [True] * len(self.dirty)
        self.read_state()

    # --- collision primitives -----------------------------------------------------------------
    def collision_parts(self):
        """[(link row, Collision)] for every primitive of every link."""
        rows = {name: i for i, name in enumerate(self.link_names)}
        return [(rows[link], c) for link, shapes in self.collisions.items()
                for c in shapes]

    def joint_names(self) -> List[str]:
        return [j.name for j in self.joints]

    def description(self) -> str:
        """The URDF with every link named as its scene object (= its TF frame), for a
        ``robot_description`` parameter: rviz's RobotModel then draws the robot from TF."""
        tree = ET.parse(self.spec.urdf)
        root = tree.getroot()
        root.set("name", self.spec.name)
        rename = {link: obj.name for link, obj in self.objects.items()}
        for link in root.iter("link"):
            link.set("name", rename.get(link.get("name"), link.get("name")))
        for joint in root.iter("joint"):
            for end in ("parent", "child"):
                element = joint.find(end)
                if element is not None:
                    element.set("link", rename.get(element.get("link"), element.get("link")))
        return ET.tostring(root, encoding="unicode")

    def movable_index(self, name: str) -> Optional[int]:
        for k, j in enumerate(self.joints):
            if j.name == name:
                return k
        return None


__all__ = ["ArmJoint", "ArticulatedRobot", "Collision", "POSITION", "VELOCITY",
           "parse_collisions"]

"""Forward kinematics of a URDF kinematic tree in numpy: an independent check on pybullet.

``load_urdf_chain`` parses a plain URDF file with xml.etree; ``Chain.forward`` gives every link's
world pose, ``(position (3,), quaternion (x, y, z, w))``, for joint positions and a base pose.
Joints are kept in the order pybullet numbers them: depth first from the root link, the children
of a link in the order their joints appear in the file.
"""
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from epuck_vrep_compat.geometry.transforms import (
    IDENTITY_QUAT, compose, quat_from_axis_angle, quat_from_rpy)

MOVABLE_TYPES = ("revolute", "continuous", "prismatic")
_ZERO = np.zeros(3)


@dataclass(frozen=True)
class JointLimits:
    """A URDF joint's limits."""
    lower: float       # rad or m; -inf for a continuous joint
    upper: float       # rad or m; +inf for a continuous joint
    velocity: float    # rad/s or m/s; inf when the file gives none
    effort: float      # N·m or N; inf when the file gives none


@dataclass(frozen=True)
class Joint:
    """A URDF joint: type, links, origin, axis and limits."""
    name: str
    joint_type: str
    parent: str
    child: str
    origin_position: np.ndarray   # child frame at zero in the parent frame [m]
    origin_quat: np.ndarray       # x, y, z, w
    axis: np.ndarray              # unit vector in the child frame
    limits: JointLimits           # None for a fixed joint


class Chain:
    """A URDF tree: ``joint_names`` (movable, pybullet's order), ``limits``, ``forward()``."""

    def __init__(self, root, joints):
        self.root = root
        self.joints = tuple(joints)
        movable = [j for j in self.joints if j.joint_type in MOVABLE_TYPES]
        self.joint_names = tuple(j.name for j in movable)
        self.limits = {j.name: j.limits for j in movable}
        self.link_names = (root,) + tuple(j.child for j in self.joints)

    def joint_positions(self, q):
        """``q`` as a dict name -> position; missing joints are at 0, unknown names rejected."""
        if q is None:
            return {}
        if isinstance(q, dict):
            unknown = set(q) - set(self.joint_names)
            if unknown:
                raise ValueError(f"not movable joints of this model: {sorted(unknown)}")
            return {name: float(value) for name, value in q.items()}
        values = np.asarray(q, dtype=float).ravel()
        if values.size != len(self.joint_names):
            raise ValueError(f"expected {len(self.joint_names)} joint positions, got {values.size}")
        return dict(zip(self.joint_names, values.tolist()))

    def forward(self, q=None, base_position=_ZERO, base_quat=IDENTITY_QUAT):
        """World pose of every link frame: dict link name -> (position, quaternion x, y, z, w)."""
        positions = self.joint_positions(q)
        poses = {self.root: (np.asarray(base_position, dtype=float),
                             np.asarray(base_quat, dtype=float))}
        for joint in self.joints:    # tree order: a parent's pose is known before its children
            p, r = compose(*poses[joint.parent], joint.origin_position, joint.origin_quat)
            poses[joint.child] = compose(p, r, *_motion(joint, positions.get(joint.name, 0.0)))
        return poses


def _motion(joint, value):
    """The child's displacement by the joint's own motion, in the joint frame."""
    if joint.joint_type == "prismatic":
        return joint.axis * value, IDENTITY_QUAT
    if joint.joint_type in ("revolute", "continuous"):
        return _ZERO, quat_from_axis_angle(joint.axis, value)
    return _ZERO, IDENTITY_QUAT


def _floats(text, default):
    return np.array([float(v) for v in text.split()]) if text else np.array(default, dtype=float)


def _limits(element, joint_type):
    if joint_type == "fixed":
        return None
    limit = element.find("limit")
    if limit is None and joint_type != "continuous":
        raise ValueError(f"joint {element.get('name')}: a {joint_type} joint needs <limit>")
    attributes = limit.attrib if limit is not None else {}
    velocity = float(attributes.get("velocity", math.inf))
    effort = float(attributes.get("effort", math.inf))
    if joint_type == "continuous":
        return JointLimits(-math.inf, math.inf, velocity, effort)
    return JointLimits(float(attributes.get("lower", 0.0)), float(attributes.get("upper", 0.0)),
                       velocity, effort)


def _parse_joint(element):
    name, joint_type = element.get("name"), element.get("type")
    if joint_type not in MOVABLE_TYPES + ("fixed",):
        raise ValueError(f"joint {name}: unsupported type {joint_type!r}")
    origin = element.find("origin")
    xyz = _floats(origin.get("xyz") if origin is not None else None, (0, 0, 0))
    rpy = _floats(origin.get("rpy") if origin is not None else None, (0, 0, 0))
    axis_element = element.find("axis")
    axis = _floats(axis_element.get("xyz") if axis_element is not None else None, (1, 0, 0))
    return Joint(name, joint_type, element.find("parent").get("link"),
                 element.find("child").get("link"), xyz, np.asarray(quat_from_rpy(*rpy)),
                 axis / np.linalg.norm(axis), _limits(element, joint_type))


def load_urdf_chain(path):
    """Parse the URDF file at ``path`` into a :class:`Chain` (ValueError if it is no tree)."""
    robot = ET.parse(path).getroot()
    links = [link.get("name") for link in robot.findall("link")]
    joints = [_parse_joint(element) for element in robot.findall("joint")]
    children = {link: [] for link in links}
    for joint in joints:
        if joint.parent not in children or joint.child not in children:
            raise ValueError(f"joint {joint.name} names a link the file does not define")
        children[joint.parent].append(joint)
    roots = sorted(set(links) - {joint.child for joint in joints})
    if len(roots) != 1:
        raise ValueError(f"{path}: expected one root link, found {roots}")
    ordered, stack = [], list(reversed(children[roots[0]]))
    while stack:
        joint = stack.pop()
        ordered.append(joint)
        stack.extend(reversed(children[joint.child]))
    if len(ordered) != len(joints):
        raise ValueError(f"{path}: the joints do not form one tree")
    return Chain(roots[0], ordered)

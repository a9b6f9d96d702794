"""Cartesian speeds of points on a robot's links, from its joint states and its URDF (the
``/<robot>/robot_description`` the simulator sets, links named as their TF frames).

The speed of a point fixed to a link is the rate of change of its position under the joints'
motion: (p(q + q' h) - p(q)) / h by the URDF's forward kinematics, with h small (1 ms), in the
root link's frame; plus the root's own motion when the robot has a mobile base (joint states
carry none: the caller gives the root's twist, e.g. from TF, see :func:`root_twist`): the
root's linear velocity plus its angular velocity crossed with the point's position.
"""
import io
import math
from typing import Dict, Sequence

import numpy as np

from epuck_vrep_compat.geometry.transforms import (
    quat_conj, quat_from_axis_angle, quat_mul_terms, quat_rotate, rotate_terms, yaw_of)
from epuck_vrep_compat.geometry.urdf_kinematics import load_urdf_chain

STEP_S = 1e-3


class LinkSpeeds:
    """Forward kinematics of one robot, for the speeds of points on its links."""

    def __init__(self, description_xml: str):
        self.chain = load_urdf_chain(io.StringIO(description_xml))
        self.links = set(self.chain.link_names)
        self._joints = [(j, _floats3(j.origin_position), tuple(j.origin_quat.tolist()),
                         _motion_of(j)) for j in self.chain.joints]

    @property
    def root(self) -> str:
        """The root link (its TF frame: the robot's base object)."""
        return self.chain.link_names[0]

    def speeds(self, joint_names: Sequence[str], q: Sequence[float], qd: Sequence[float],
               links: Sequence[str], local_points, root_linear=None,
               root_angular=None) -> np.ndarray:
        """Speed (m/s) of each point local_points[i] (in the frame of links[i]); NaN for a
        link the URDF does not have. ``root_linear``, ``root_angular``: the root link's
        velocity (3, each) in its own frame; None: at rest."""
        v_root = (0.0, 0.0, 0.0) if root_linear is None else _floats3(root_linear)
        w_root = (0.0, 0.0, 0.0) if root_angular is None else _floats3(root_angular)
        known = set(self.chain.joint_names)
        now: Dict[str, float] = {}
        ahead: Dict[str, float] = {}
        for name, value, rate in zip(joint_names, q, qd):
            if name in known:
                now[name] = float(value)
                ahead[name] = float(value) + float(rate) * STEP_S
        poses_now, poses_ahead = self._forward(now), self._forward(ahead)
        out = np.full(len(links), np.nan)
        for i, (link, point) in enumerate(zip(links, local_points)):
            if link in self.links:
                point = _floats3(point)
                a = _compose_point(*poses_now[link], point)
                b = _compose_point(*poses_ahead[link], point)
                w0, w1, w2 = w_root           # numpy's cross, term by term
                cross = (w1 * a[2] - w2 * a[1], w2 * a[0] - w0 * a[2], w0 * a[1] - w1 * a[0])
                velocity = np.array([(b[k] - a[k]) / STEP_S + v_root[k] + cross[k]
                                     for k in range(3)])
                out[i] = math.sqrt(velocity.dot(velocity))      # np.linalg.norm's own sum
        return out

    def _forward(self, positions):
        """:meth:`Chain.forward` at the origin, in plain floats: the same operations in the
        same order (:func:`geometry.transforms.compose` on one pose), so the same bits, at a
        tenth of the cost."""
        poses = {self.chain.root: ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))}
        for joint, origin_p, origin_q, motion in self._joints:
            p, r = _compose(*poses[joint.parent], origin_p, origin_q)
            poses[joint.child] = _compose(p, r, *motion(positions.get(joint.name, 0.0)))
        return poses


_IDENTITY = (0.0, 0.0, 0.0, 1.0)
_ZERO = (0.0, 0.0, 0.0)


def _floats3(v):
    return tuple(float(x) for x in np.asarray(v, dtype=float).tolist())


def _compose_point(p, q, v):
    r = rotate_terms(q, v)
    return (p[0] + r[0], p[1] + r[1], p[2] + r[2])


def _compose(p_a, q_a, p_b, q_b):
    """``transforms.compose`` on one pose, term by term."""
    return _compose_point(p_a, q_a, p_b), quat_mul_terms(q_a, q_b)


def _motion_of(joint):
    """The joint's own motion as a function of its value (``urdf_kinematics._motion``)."""
    if joint.joint_type == "prismatic":
        axis = joint.axis
        return lambda value: (tuple((axis * value).tolist()), _IDENTITY)
    if joint.joint_type in ("revolute", "continuous"):
        axis = joint.axis
        return lambda value: (_ZERO, tuple(quat_from_axis_angle(axis, value).tolist()))
    return lambda value: (_ZERO, _IDENTITY)


def root_twist(before, after):
    """The root link's (linear, angular) velocity in its own frame between two of its world
    poses, each (stamp_s, position (3,), quaternion (x, y, z, w)); zeros when the stamps do
    not advance. Planar bases: the angular velocity is the yaw rate."""
    (t0, p0, q0), (t1, p1, q1) = before, after
    dt = t1 - t0
    if not dt > 0.0:
        return np.zeros(3), np.zeros(3)
    to_root = quat_conj(np.asarray(q1, dtype=float))          # world to root, now
    linear_world = (np.asarray(p1, dtype=float) - np.asarray(p0, dtype=float)) / dt
    yaw_rate = math.remainder(yaw_of(q1) - yaw_of(q0), 2.0 * math.pi) / dt
    return (np.asarray(quat_rotate(to_root, linear_world)),
            np.asarray(quat_rotate(to_root, np.array([0.0, 0.0, yaw_rate]))))

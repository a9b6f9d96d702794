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
    IDENTITY_QUAT, compose, quat_conj, quat_rotate, yaw_of)
from epuck_vrep_compat.geometry.urdf_kinematics import load_urdf_chain

STEP_S = 1e-3


class LinkSpeeds:
    """Forward kinematics of one robot, for the speeds of points on its links."""

    def __init__(self, description_xml: str):
        self.chain = load_urdf_chain(io.StringIO(description_xml))
        self.links = set(self.chain.link_names)

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
        v_root = np.zeros(3) if root_linear is None else np.asarray(root_linear, dtype=float)
        w_root = np.zeros(3) if root_angular is None else np.asarray(root_angular, dtype=float)
        known = set(self.chain.joint_names)
        now: Dict[str, float] = {}
        ahead: Dict[str, float] = {}
        for name, value, rate in zip(joint_names, q, qd):
            if name in known:
                now[name] = float(value)
                ahead[name] = float(value) + float(rate) * STEP_S
        poses_now, poses_ahead = self.chain.forward(now), self.chain.forward(ahead)
        out = np.full(len(links), np.nan)
        for i, (link, point) in enumerate(zip(links, local_points)):
            if link in self.links:
                a, _ = compose(*poses_now[link], point, IDENTITY_QUAT)
                b, _ = compose(*poses_ahead[link], point, IDENTITY_QUAT)
                velocity = (b - a) / STEP_S + v_root + np.cross(w_root, a)
                out[i] = float(np.linalg.norm(velocity))
        return out


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

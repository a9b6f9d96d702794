"""Cartesian speeds of points on a robot's links, from its joint states and its URDF (the
``/<robot>/robot_description`` the simulator sets, links named as their TF frames).

The speed of a point fixed to a link is the rate of change of its position under the joints'
motion: |p(q + q' h) - p(q)| / h by the URDF's forward kinematics, with h small (1 ms). The base
is taken at rest (joint states carry no base motion).
"""
import io
from typing import Dict, Sequence

import numpy as np

from epuck_vrep_compat.geometry.transforms import IDENTITY_QUAT, compose
from epuck_vrep_compat.geometry.urdf_kinematics import load_urdf_chain

STEP_S = 1e-3


class LinkSpeeds:
    """Forward kinematics of one robot, for the speeds of points on its links."""

    def __init__(self, description_xml: str):
        self.chain = load_urdf_chain(io.StringIO(description_xml))
        self.links = set(self.chain.link_names)

    def speeds(self, joint_names: Sequence[str], q: Sequence[float], qd: Sequence[float],
               links: Sequence[str], local_points) -> np.ndarray:
        """Speed (m/s) of each point local_points[i] (in the frame of links[i]); NaN for a
        link the URDF does not have."""
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
                out[i] = float(np.linalg.norm(b - a)) / STEP_S
        return out

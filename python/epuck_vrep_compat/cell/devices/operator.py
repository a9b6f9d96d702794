"""The walking operator: a primitive human (cylinder body, sphere head) that walks a polyline of
waypoints at constant speed, to its end and back, over and over. Kinematic: it goes through
robots rather than around them, as V-REP's path-following "Bill" does."""
import math

import numpy as np

from epuck_vrep_compat._core import GROUP_DYNAMIC
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import IDENTITY_QUAT, quat_from_yaw


class WalkingOperator:
    """Where the operator is along its path, as the distance walked grows."""

    def __init__(self, spec):
        self.spec = spec
        self.points = np.asarray(spec.waypoints_m, dtype=float)
        seg = np.diff(self.points, axis=0)
        self.lengths = np.hypot(seg[:, 0], seg[:, 1])
        if not (self.lengths > 0.0).all():
            raise ValueError("operator waypoints must not repeat consecutively")
        self.cumulative = np.concatenate(([0.0], np.cumsum(self.lengths)))
        self.path_length = float(self.cumulative[-1])
        self.distance = 0.0            # walked since the start, metres

    def advance(self, dt: float):
        self.distance += self.spec.speed_m_s * dt

    def reset(self):
        self.distance = 0.0

    def state(self):
        """(x, y, heading [rad], outbound?) at the current walked distance."""
        lap = math.fmod(self.distance, 2.0 * self.path_length)
        outbound = lap <= self.path_length
        s = lap if outbound else 2.0 * self.path_length - lap
        i = int(np.clip(np.searchsorted(self.cumulative, s, side="right") - 1, 0,
                        len(self.lengths) - 1))
        a, b = self.points[i], self.points[i + 1]
        t = (s - self.cumulative[i]) / self.lengths[i]
        x, y = a + t * (b - a)
        heading = math.atan2(b[1] - a[1], b[0] - a[0])
        if not outbound:
            heading = math.atan2(-math.sin(heading), -math.cos(heading))
        return float(x), float(y), heading, outbound

    def pose(self):
        """Base frame on the floor under the body's axis, x = walking direction."""
        x, y, heading, _ = self.state()
        return np.array([x, y, 0.0]), quat_from_yaw(heading)

    @property
    def body_centre_z(self) -> float:
        return 0.5 * self.spec.body_height_m

    @property
    def head_centre_z(self) -> float:
        return self.spec.body_height_m + self.spec.head_radius_m

    @property
    def height(self) -> float:
        return self.spec.body_height_m + 2.0 * self.spec.head_radius_m


def add_operator(spec, registry, world):
    """The operator of ``spec`` (an OperatorSpec) into the scene: its body (a cylinder whose
    pose follows the walk) and head (a sphere on it), in the registry and the collision world.
    Returns (the WalkingOperator, (body handle, head handle))."""
    operator = WalkingOperator(spec)
    base = registry.add(spec.name, vc.OBJECT_SHAPE, vc.WORLD, pose_source=operator.pose,
                        properties=dict(shape="cylinder", color=spec.color))
    world.add_cylinder(base.handle, spec.body_radius_m, spec.body_height_m, np.zeros(3),
                       IDENTITY_QUAT, spec.color, GROUP_DYNAMIC)
    head = registry.add(spec.name + "_head", vc.OBJECT_SHAPE, base.handle,
                        (0.0, 0.0, operator.head_centre_z),
                        properties=dict(shape="sphere", color=spec.color))
    world.add_sphere(head.handle, spec.head_radius_m, np.zeros(3), IDENTITY_QUAT, spec.color,
                     GROUP_DYNAMIC)
    return operator, (base.handle, head.handle)

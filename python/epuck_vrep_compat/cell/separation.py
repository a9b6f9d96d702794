"""The separation between the operator and the cell's robots: for every link with a collision
shape, the closest points between the operator's body (cylinder and head) and the link's
primitives, computed by the C++ core on the simulation's own collision world.

The operator is either where he is (ground truth: his objects in the world) or his body stood
at a given (x, y) on the floor, e.g. where a tracker believes he is. What a speed-and-separation
supervisor asks of the simulator; the ROS face offers it as a service.
"""
from dataclasses import dataclass
from typing import List

import numpy as np

from epuck_vrep_compat._core import ConvexShape
from epuck_vrep_compat.geometry.transforms import IDENTITY_QUAT, rotate_terms


@dataclass
class LinkSeparation:
    """One link's closest points to the operator (world frame, and on the link in its own)."""
    robot: str
    link: str                   # the link's scene object (= its TF frame)
    distance_m: float           # < 0: overlapping
    operator_point: np.ndarray
    link_point: np.ndarray
    link_point_local: np.ndarray


class NoOperator(ValueError):
    """The cell has no operator to measure from."""


def _operator_body(cell, x: float, y: float):
    """(shapes, positions, quaternions) of the operator's body stood at (x, y)."""
    spec = cell.spec.operator
    if spec is None:
        raise NoOperator("the cell has no operator")
    shapes = [ConvexShape.cylinder(spec.body_radius_m, spec.body_height_m),
              ConvexShape.sphere(spec.head_radius_m)]
    positions = np.array([[x, y, 0.5 * spec.body_height_m],
                          [x, y, spec.body_height_m + spec.head_radius_m]])
    return shapes, positions, np.tile(IDENTITY_QUAT, (2, 1))


@dataclass
class Separations:
    """Every link's closest points to the operator, stacked (n links): what
    :func:`operator_separation` gives as one :class:`LinkSeparation` each."""
    robot: List[str]
    link: List[str]
    distance_m: np.ndarray          # (n,)
    operator_point: np.ndarray      # (n, 3), world frame
    link_point: np.ndarray          # (n, 3), world frame
    link_point_local: np.ndarray    # (n, 3), in each link's frame


def _rotate_rows(q, v):
    """Rows ``v`` (n, 3) rotated by rows ``q`` (n, 4), by the one-pose formula term by term, so
    that each row is what ``quat_rotate`` gives for it alone, to the last bit."""
    return np.column_stack(rotate_terms(q.T, v.T))


def separations(cell, ground_truth: bool = True, x: float = 0.0, y: float = 0.0) -> Separations:
    """Every link's separation from the operator, as of the last step, stacked. NoOperator
    when there is none to measure from (ground truth needs him in the scene); ValueError for a
    non-finite (x, y)."""
    links = cell.link_collisions
    names = [(arm, name) for arm in cell.arms for name in arm.link_names]
    groups = len(names)
    handles, rows = links.handles.tolist(), links.rows.tolist()
    if ground_truth:
        if cell.operator is None:
            raise NoOperator("the operator is not in the scene")
        d, pa, pb, _, _ = cell.sim.world.minimum_distances(
            list(cell.operator_handles), handles, rows, groups)
    else:
        if not (np.isfinite(x) and np.isfinite(y)):
            raise ValueError(f"operator position ({x}, {y}) is not finite")
        shapes, positions, quats = _operator_body(cell, x, y)
        d, pa, pb, _, _ = cell.sim.world.minimum_distances_to(
            shapes, positions, quats, handles, rows, groups)
    link_positions, link_quats = cell.link_poses()
    used = sorted(set(rows))
    conj = np.array(link_quats[used], dtype=float).reshape(-1, 4)
    conj[:, :3] *= -1.0                                     # the links' inverse poses
    back = -_rotate_rows(conj, np.asarray(link_positions[used], dtype=float).reshape(-1, 3))
    points = np.asarray(pb[used], dtype=float).reshape(-1, 3)
    return Separations([names[r][0].spec.name for r in used],
                       [names[r][0].objects[names[r][1]].name for r in used],
                       np.asarray(d[used], dtype=float), np.array(pa[used], dtype=float),
                       np.array(points), back + _rotate_rows(conj, points))


def operator_separation(cell, ground_truth: bool = True, x: float = 0.0,
                        y: float = 0.0) -> List[LinkSeparation]:
    """:func:`separations`, one :class:`LinkSeparation` per link."""
    s = separations(cell, ground_truth, x, y)
    return [LinkSeparation(s.robot[i], s.link[i], float(s.distance_m[i]),
                           s.operator_point[i].copy(), s.link_point[i].copy(),
                           s.link_point_local[i].copy()) for i in range(len(s.robot))]

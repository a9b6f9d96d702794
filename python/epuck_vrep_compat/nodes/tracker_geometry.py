"""The operator tracker's geometry: blob cameras and the laser as position measurements on the
floor (numpy only, no ROS).

Cameras: a V-REP vision sensor looks along its +z axis, +y up in the image and +x towards the
image's left; with f = 0.5 / tan(angle / 2), a point p_c in the camera frame is seen at
u = 0.5 - f x_c / z_c (from the left), v = 0.5 + f y_c / z_c (from the bottom). A blob at (u, v)
is thus the ray d_c = ((0.5 - u) / f, (v - 0.5) / f, 1) from the camera's centre. The blob is
the operator's silhouette's bounding box, whose centre lies near his mid-height: two cameras'
rays meet (least squares) there; one camera's ray is cut at that height.

Laser: returns short of the background (the farthest seen per beam) become world points; consecutive returns closer than a gap form a
cluster; a cluster as wide as a person is one candidate, its centre the arc's centroid pushed
back by 2 r / pi (a cylinder of radius r shows the scanner a half circle).
"""
import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from epuck_vrep_compat.geometry.transforms import nearest_rotation, quat_rotate

# The thesis's calibration (its Code 3.1): the ceiling cameras' V-REP object matrices (rows of
# [R | t]) relative to "Plane", the floor. Camera 0 is the object "camera0", camera 1 "camera".
THESIS_CAMERA_MATRICES = (
    (-0.9981, 0.0493, -0.0358, -0.8468, 0.0507, 0.9979, -0.0412, 1.5771,
     0.0337, -0.0429, -0.9985, 2.8421),
    (-0.9983, 0.0558, 0.0183, 1.4507, 0.0543, 0.9956, -0.0770, 1.6420,
     -0.0225, -0.0759, -0.9969, 2.8738),
)
VIEW_ANGLE_DEG = 80.0
# where the two cameras' rays meet, measured in this cell (the silhouette's box centre sits
# below his mid-height, seen from above); one camera's ray is cut there
BLOB_HEIGHT_M = 0.6
BODY_RADIUS_M = 0.2


class BlobCamera:
    """One calibrated camera: the world ray through a blob position."""

    def __init__(self, matrix: Sequence[float], view_angle_deg: float = VIEW_ANGLE_DEG):
        m = np.asarray(matrix, dtype=float).reshape(3, 4)
        self.rotation = nearest_rotation(m[:, :3])  # the printed matrix is rounded
        self.centre = m[:, 3].copy()
        self.focal = 0.5 / math.tan(math.radians(view_angle_deg) / 2.0)

    def ray(self, u: float, v: float) -> np.ndarray:
        """Unit world direction of the blob at (u, v) (0..1, u from the left, v from the
        bottom)."""
        d = self.rotation @ np.array([(0.5 - u) / self.focal, (v - 0.5) / self.focal, 1.0])
        return d / np.linalg.norm(d)

    def at_height(self, u: float, v: float, height_m: float = BLOB_HEIGHT_M):
        """(x, y) where the blob's ray crosses the height, or None if it never does."""
        d = self.ray(u, v)
        if abs(d[2]) < 1e-9:
            return None
        t = (height_m - self.centre[2]) / d[2]
        if t <= 0:
            return None
        p = self.centre + t * d
        return np.array([p[0], p[1]])


def triangulate(origins, directions) -> Optional[np.ndarray]:
    """The point nearest (least squares) to every ray; None for (near-)parallel rays."""
    a, b = np.zeros((3, 3)), np.zeros(3)
    for o, d in zip(origins, directions):
        m = np.eye(3) - np.outer(d, d)
        a += m
        b += m @ o
    if np.linalg.cond(a) > 1e8:
        return None
    return np.linalg.solve(a, b)


class LaserBackground:
    """What the laser sees when nobody moves: per beam the farthest return so far (people and
    moving robots only ever come nearer). A return well short of it is foreground."""

    def __init__(self, margin_m: float = 0.15):
        self.margin_m = margin_m
        self.farthest = None

    def foreground(self, ranges) -> np.ndarray:
        """The ranges with background returns (and the first scan, all background) as inf."""
        r = np.asarray(ranges, dtype=float)
        finite = np.where(np.isfinite(r), r, np.inf)
        if self.farthest is None or self.farthest.shape != r.shape:
            self.farthest = finite.copy()
            return np.full(r.shape, np.inf)
        self.farthest = np.maximum(self.farthest, finite)
        return np.where(finite < self.farthest - self.margin_m, finite, np.inf)


def scan_points(ranges, angle_min, angle_increment, position, quat) -> np.ndarray:
    """(N, 2) world x, y of the finite returns of a scan taken at position, turned by quat
    (x, y, z, w)."""
    r = np.asarray(ranges, dtype=float)
    angles = angle_min + angle_increment * np.arange(r.size)
    ok = np.isfinite(r)
    local = np.stack((r[ok] * np.cos(angles[ok]), r[ok] * np.sin(angles[ok]),
                      np.zeros(int(ok.sum()))), axis=1)
    world = quat_rotate(np.broadcast_to(np.asarray(quat, dtype=float), (len(local), 4)),
                        local) + np.asarray(position)
    return world[:, :2]


def person_candidates(points, scanner_xy, gap_m=0.15, min_width_m=0.1,
                      max_width_m=0.7) -> List[np.ndarray]:
    """Centres of the clusters of consecutive points as wide as a person."""
    if len(points) == 0:
        return []
    breaks = np.flatnonzero(np.linalg.norm(np.diff(points, axis=0), axis=1) > gap_m) + 1
    out = []
    for cluster in np.split(points, breaks):
        width = float(np.linalg.norm(cluster[-1] - cluster[0]))
        if len(cluster) < 3 or not min_width_m <= width <= max_width_m:
            continue
        centroid = cluster.mean(axis=0)
        away = centroid - np.asarray(scanner_xy)
        out.append(centroid + 2.0 * BODY_RADIUS_M / math.pi * away / np.linalg.norm(away))
    return out


def nearest(candidates, predicted, gate_m) -> Tuple[Optional[np.ndarray], float]:
    """The candidate nearest the prediction within the gate, and its distance."""
    best, best_d = None, gate_m
    for c in candidates:
        d = float(np.linalg.norm(c - predicted))
        if d <= best_d:
            best, best_d = c, d
    return best, best_d

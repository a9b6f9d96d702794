"""The cell's sensor components, as the ``/vrep`` services read them: ray proximity sensors
(read from the cell's last step) and vision sensors with V-REP's "entity to render" mask, depth
noise and blob filter; and V-REP's 12-value object matrices as poses (the thesis's camera
calibration).
"""
import math

import numpy as np

from epuck_vrep_compat import _core
from epuck_vrep_compat._core import GROUP_ALL
from epuck_vrep_compat.devices.components import VisionSensor
from epuck_vrep_compat.scene import vrep_codes as vc


def quat_from_matrix(m):
    """Unit quaternion (x, y, z, w) of a 3x3 rotation matrix (re-orthonormalised first)."""
    u, _, vt = np.linalg.svd(np.asarray(m, dtype=float))
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] *= -1.0
        r = u @ vt
    t = np.trace(r)
    if t > 0:
        s = 2.0 * math.sqrt(t + 1.0)
        q = ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, 0.25 * s)
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
        q[i] = 0.25 * s
        q[j] = (r[j, i] + r[i, j]) / s
        q[k] = (r[k, i] + r[i, k]) / s
    q = np.array(q)
    return q / np.linalg.norm(q)


def pose_from_vrep_matrix(values):
    """V-REP's 12-value object matrix (rows of [R | t]) to (position, quaternion)."""
    m = np.asarray(values, dtype=float).reshape(3, 4)
    return m[:, 3].copy(), quat_from_matrix(m[:, :3])


class RayProximity:
    """A ray-type proximity sensor (V-REP: detection along its z axis), read from the cell's
    last step."""

    subtype = vc.PROXSENSOR_RAY

    def __init__(self, cell, index: int):
        self._cell = cell
        self._index = index

    def read(self):
        """(detection state 0/1, point in the sensor frame (3), object handle or -1, normal)."""
        c = self._cell
        i = self._index
        if not c.prox_state[i]:
            return 0, np.zeros(3), -1, np.zeros(3)
        return 1, c.prox_point[i].copy(), int(c.prox_handle[i]), c.prox_normal[i].copy()


class CellVision(VisionSensor):
    """A vision sensor of the cell: optional render mask (V-REP's "entity to render"), optional
    depth noise (Kinect), and the blob filter's packet (ceiling cameras)."""

    def __init__(self, sim, handle, spec, mask=GROUP_ALL, depth_noise=None, blob=False):
        super().__init__(sim, handle, spec)
        self.mask = mask
        self.depth_noise = depth_noise
        self.blob = blob

    def render(self):
        position, quat = self.camera_pose()
        s = self.spec
        rgb, depth = self._sim.world.render(position, quat, s.width, s.height,
                                            s.vertical_fov_rad, s.near_m, s.far_m, -1,
                                            self.mask)
        if self.depth_noise is not None:
            depth = self.depth_noise.apply(depth, s.near_m, s.far_m)
        return rgb, depth

    def blob_packet(self):
        """V-REP's blob detection filter on what the sensor renders (pixels where a ray hit
        something): [count, 6, size, orientation, x, y, w, h, ...], x and y relative to the
        image, y from the bottom."""
        _, depth = self.render()
        return np.asarray(_core.detect_blobs((depth < self.spec.far_m).astype(np.uint8)),
                          dtype=float)

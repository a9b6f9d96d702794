"""The Kinect's depth of the operator, for the tracker: a range measurement along its view ray.

The depth image (``/kinect/depth/image``, 32FC1, metres along the optical axis, REP 118, from
the thesis's ``[/kinect]`` node) is a V-REP vision sensor's: it looks along its frame's +z, +x
towards the image's left, +y up, its horizontal angle spanning the width. The tracker's
estimate, at the body's centre height, is projected into the image; the median depth of a
window about it, if near the expected one (nothing in front of him), is back-projected to the
body's front surface, and pushed back by the body's radius along the horizontal ray. The image
position came from the estimate itself, so only the range is new: the measurement's covariance
is the depth noise (σ_z = 0.0012 + 0.0019 (z - 0.4)^2 m, Nguyen et al. 2012, plus the body's
shape) along the ray and uninformative across it.
"""
import math

import numpy as np

from epuck_vrep_compat.geometry.transforms import quat_conj, quat_rotate

BODY_CENTRE_M = 0.65
BODY_RADIUS_M = 0.2
SHAPE_SIGMA_M = 0.05          # the body's surface is not a cylinder's: what the window sees
ACROSS_SIGMA_M = 3.0          # no information across the ray
WINDOW_PX = 5                 # half width of the window
OCCLUSION_M = 0.6             # a median nearer than expected by this much: something in front


def depth_sigma(z):
    return 0.0012 + 0.0019 * (z - 0.4) ** 2


class KinectRange:
    """The depth sensor's geometry (pose in the world, horizontal angle) and the measurement."""

    def __init__(self, horizontal_fov_deg: float = 57.0):
        self.half_tan = math.tan(math.radians(horizontal_fov_deg) / 2.0)

    def measurement(self, depth, position, quat, estimate_xy):
        """(xy, R) from a depth image (H, W) taken at position/quat, about the estimate; None
        when he is out of view, occluded or the window holds no return."""
        h, w = depth.shape
        focal = 0.5 * w / self.half_tan
        target = np.array([estimate_xy[0], estimate_xy[1], BODY_CENTRE_M])
        local = quat_rotate(quat_conj(quat), target - position)
        if local[2] <= 0.3:
            return None
        col = int(round(0.5 * w - focal * local[0] / local[2]))
        row = int(round(0.5 * h - focal * local[1] / local[2]))
        if not (WINDOW_PX <= col < w - WINDOW_PX and WINDOW_PX <= row < h - WINDOW_PX):
            return None
        window = depth[row - WINDOW_PX:row + WINDOW_PX + 1, col - WINDOW_PX:col + WINDOW_PX + 1]
        window = window[np.isfinite(window)]
        if window.size < 5:
            return None
        z = float(np.median(window))
        expected = local[2] - BODY_RADIUS_M
        if abs(z - expected) > OCCLUSION_M:
            return None
        surface = position + quat_rotate(quat, local * (z / local[2]))
        ray = surface[:2] - position[:2]
        ray /= np.linalg.norm(ray)
        centre = surface[:2] + BODY_RADIUS_M * ray
        along = depth_sigma(z) ** 2 + SHAPE_SIGMA_M ** 2
        cov = along * np.outer(ray, ray) + ACROSS_SIGMA_M ** 2 * (np.eye(2) - np.outer(ray, ray))
        return centre, cov

"""Neighbours' range and bearing, the observation's last block, from poses (x, y, yaw): in the
environments from the core's ground truth, under ROS from the ``ground_truth`` topics (the
simulator's; on real robots whatever tracker publishes the poses).

The bearing's arctangent, cosine and sine are the C library's (``math``'s, element by element:
:func:`epuck_vrep_compat.geometry.fixed_order.libm`), not numpy's kernels, which differ in the
last bits between processors (SVML on AVX-512); so the block is the same bits on any
processor, for one robot (:func:`block`) and for a batch (:func:`blocks`)."""
import math

import numpy as np

from epuck_vrep_compat.geometry.fixed_order import libm


def block(own_pose, other_xy, count: int, range_m: float) -> np.ndarray:
    """(3 * count,) for one robot at ``own_pose`` (3,) among ``other_xy`` (M, 2): per slot,
    nearest first, ``1 - d / range_m``, cos and sin of the bearing; zeros past the robots in
    range."""
    out = np.zeros(3 * count)
    others = np.asarray(other_xy, dtype=float).reshape(-1, 2)
    if count == 0 or len(others) == 0:
        return out
    x, y, yaw = (float(v) for v in own_pose)
    dx, dy = others[:, 0] - x, others[:, 1] - y
    d = np.hypot(dx, dy)
    order = [i for i in np.argsort(d, kind="stable") if d[i] < range_m][:count]
    for slot, i in enumerate(order):
        bearing = math.atan2(dy[i], dx[i]) - yaw
        out[3 * slot:3 * slot + 3] = (1.0 - d[i] / range_m, math.cos(bearing), math.sin(bearing))
    return out


def blocks(poses, count: int, range_m: float, groups: int = 1) -> np.ndarray:
    """(N, 3 * count) for every robot of ``poses`` (N, 3), whose rows are ``groups`` equal
    runs of robots that see only each other (the batched worlds' rows: world * R + robot);
    the same values as :func:`block` robot by robot."""
    poses = np.asarray(poses, dtype=float)
    n = len(poses)
    per = n // groups
    out = np.zeros((n, 3 * count))
    if count == 0 or per < 2:
        return out
    p = poses.reshape(groups, per, 3)
    dx = p[:, None, :, 0] - p[:, :, None, 0]          # (G, me, other)
    dy = p[:, None, :, 1] - p[:, :, None, 1]
    d = np.hypot(dx, dy)
    d[:, np.arange(per), np.arange(per)] = np.inf      # not oneself
    order = np.argsort(d, axis=-1, kind="stable")[..., :count]
    near = np.take_along_axis(d, order, -1)
    bearing = (libm(math.atan2, np.take_along_axis(dy, order, -1),
                    np.take_along_axis(dx, order, -1)) - p[:, :, 2:3])
    seen = near < range_m
    slots = np.stack([np.where(seen, 1.0 - near / range_m, 0.0),
                      np.where(seen, libm(math.cos, bearing), 0.0),
                      np.where(seen, libm(math.sin, bearing), 0.0)], axis=-1)   # (G, me, slot, 3)
    out[:, :3 * slots.shape[2]] = slots.reshape(n, -1)
    return out

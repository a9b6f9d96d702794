"""Rigid transforms as numpy arrays: positions (..., 3), quaternions (..., 4) as x, y, z, w.

Vectorised over leading axes so a step's transforms for every robot are one call.
"""
import math

import numpy as np

IDENTITY_QUAT = np.array([0.0, 0.0, 0.0, 1.0])


def quat_from_yaw(yaw):
    """Rotation about z by ``yaw`` [rad]; works on scalars and arrays."""
    half = 0.5 * np.asarray(yaw, dtype=float)
    q = np.zeros(half.shape + (4,))
    q[..., 2] = np.sin(half)
    q[..., 3] = np.cos(half)
    return q


def quat_from_axis_angle(axis, angle):
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    half = 0.5 * np.asarray(angle, dtype=float)
    q = np.zeros(half.shape + (4,))
    q[..., :3] = np.multiply.outer(np.sin(half), axis)
    q[..., 3] = np.cos(half)
    return q


def quat_from_rpy(roll, pitch, yaw):
    """Fixed-axis roll, pitch, yaw (ROS convention: R = Rz(yaw) Ry(pitch) Rx(roll)) [rad];
    works on scalars and arrays."""
    half = 0.5 * np.array(np.broadcast_arrays(roll, pitch, yaw), dtype=float)
    (cr, cp, cy), (sr, sp, sy) = np.cos(half), np.sin(half)
    return np.stack((sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                     cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy), axis=-1)


def quat_mul_terms(a, b):
    """The product of quaternions ``a``, ``b`` given as their four components each (floats or
    arrays of them), as a tuple of four: the one formula every product here uses, so that a
    caller working on plain floats or on columns gets the same bits as :func:`quat_mul`."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def rotate_terms(q, v):
    """``v`` rotated by the unit quaternion ``q``, both given as their components (floats or
    arrays of them), as a tuple of three: the formula of :func:`quat_rotate` on one pose."""
    x, y, z, w = q
    vx, vy, vz = v
    tx, ty, tz = 2.0 * (y * vz - z * vy), 2.0 * (z * vx - x * vz), 2.0 * (x * vy - y * vx)
    return (vx + w * tx + y * tz - z * ty,
            vy + w * ty + z * tx - x * tz,
            vz + w * tz + x * ty - y * tx)


def _mul4(a, b):
    return np.array(quat_mul_terms(a, b))


def _rotate3(q, v):
    return np.array(rotate_terms(q, v))


def quat_mul(a, b):
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if a.ndim == 1 and b.ndim == 1:
        return _mul4(a.tolist(), b.tolist())     # one pose: plain floats beat numpy's overhead
    return np.stack(quat_mul_terms(np.moveaxis(a, -1, 0), np.moveaxis(b, -1, 0)), axis=-1)


def quat_conj(q):
    q = np.array(q, dtype=float)
    q[..., :3] *= -1.0
    return q


def quat_rotate(q, v):
    """Rotate vectors ``v`` (..., 3) by unit quaternions ``q`` (..., 4)."""
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    if q.ndim == 1 and v.ndim == 1:
        return _rotate3(q.tolist(), v.tolist())
    u = q[..., :3]
    w = q[..., 3:4]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def compose(p_a, q_a, p_b, q_b):
    """Pose of frame b in the parent of a, given b in a: (p_a, q_a) * (p_b, q_b)."""
    return np.asarray(p_a) + quat_rotate(q_a, p_b), quat_mul(q_a, q_b)


def inverse(p, q):
    qi = quat_conj(q)
    return -quat_rotate(qi, p), qi


def yaw_of(q):
    q = np.asarray(q, dtype=float)
    x, y, z, w = np.moveaxis(q, -1, 0)
    return np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def normalized_quat(q):
    """Unit quaternion, or None when ``q`` is zero or not finite (callers reject it)."""
    q = np.asarray(q, dtype=float)
    n = np.linalg.norm(q)
    if not np.isfinite(n) or n < 1e-9:
        return None
    return q / n


def vrep_euler_angles(quat):
    """V-REP's Euler angles (alpha, beta, gamma) of a quaternion (x, y, z, w): the rotation is
    Rx(alpha) Ry(beta) Rz(gamma), as simGetObjectOrientation reports it. beta is
    ``atan2(r02, hypot(r12, r22))`` (asin of r02 loses half the digits near +-pi/2); below a
    cos(beta) of 1e-6 (gimbal lock) all of the z rotation goes into alpha."""
    x, y, z, w = (float(v) for v in quat)
    r02 = 2.0 * (x * z + w * y)
    r12 = 2.0 * (y * z - w * x)
    r22 = 1.0 - 2.0 * (x * x + y * y)
    r01 = 2.0 * (x * y - w * z)
    r00 = 1.0 - 2.0 * (y * y + z * z)
    cos_beta = math.hypot(r12, r22)
    beta = math.atan2(r02, cos_beta)
    if cos_beta < 1e-6:               # gimbal lock: put all of the z rotation into alpha
        r21 = 2.0 * (y * z + w * x)
        r11 = 1.0 - 2.0 * (x * x + z * z)
        return [math.atan2(r21, r11), beta, 0.0]
    return [math.atan2(-r12, r22), beta, math.atan2(-r01, r00)]


def nearest_rotation(m):
    """The rotation matrix nearest a 3x3 matrix (a printed, rounded one re-orthonormalised)."""
    u, _, vt = np.linalg.svd(np.asarray(m, dtype=float))
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] *= -1.0
        r = u @ vt
    return r


def quat_from_matrix(m):
    """Unit quaternion (x, y, z, w) of a 3x3 rotation matrix (re-orthonormalised first)."""
    r = nearest_rotation(m)
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

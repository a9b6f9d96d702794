"""Pre-serialised ROS 1 messages for the per-step publishing path.

A step of a many-robot simulation publishes thousands of small messages; building genpy objects
and serialising them field by field costs more than the physics. The messages published every
step have a fixed layout, so their wire bytes are packed here directly, with the strings encoded
once. ``test/unit/test_wire.py`` checks every encoder byte for byte against genpy.
"""
import math
import struct

import numpy as np
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, Range
from tf2_msgs.msg import TFMessage


class WireMessage:
    """A message already in wire format; rospy writes its bytes as they are.

    rospy accepts any object whose ``_md5sum`` matches the publisher's type; ``_has_header`` is
    False so rospy does not overwrite ``header.seq`` (V-REP's messages carry seq 0 anyway).
    """

    __slots__ = ("_md5sum", "_type", "_bytes")
    _has_header = False

    def __init__(self, msg_class, data: bytes):
        self._md5sum = msg_class._md5sum
        self._type = msg_class._type
        self._bytes = data

    def serialize(self, buff):
        buff.write(self._bytes)


def _string(s: str) -> bytes:
    b = s.encode("utf-8")
    return struct.pack("<I", len(b)) + b


def header_bytes(frame_id: str, secs: int, nsecs: int, seq: int = 0) -> bytes:
    return struct.pack("<3I", seq, secs, nsecs) + _string(frame_id)


class RangeWire:
    """``sensor_msgs/Range`` with fixed frame, radiation type and limits."""

    def __init__(self, frame_id, radiation_type, field_of_view, min_range, max_range):
        self._frame = _string(frame_id)
        self._tail = struct.Struct("<B4f")
        self._fixed = (radiation_type, field_of_view, min_range, max_range)

    def pack(self, secs: int, nsecs: int, range_m: float) -> WireMessage:
        data = (struct.pack("<3I", 0, secs, nsecs) + self._frame
                + self._tail.pack(*self._fixed, range_m))
        return WireMessage(Range, data)


_COV_0_01 = struct.pack("<9d", 0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01)
_COV_ZERO = struct.pack("<9d", *([0.0] * 9))
_VEC3 = struct.Struct("<3d")
_QUAT = struct.Struct("<4d")


class ImuWire:
    """``sensor_msgs/Imu`` as the V-REP model or the driver fills it.

    ``orientation_known`` False leaves orientation and its covariance zero (V-REP never sets
    them); True writes the given quaternion with covariance diag(0.01) (the driver writes yaw 0).
    """

    def __init__(self, frame_id: str, orientation_known: bool):
        self._frame = _string(frame_id)
        self._orientation_known = orientation_known

    def pack(self, secs, nsecs, accel, gyro, orientation_xyzw=(0.0, 0.0, 0.0, 1.0)):
        if self._orientation_known:
            orientation = _QUAT.pack(*orientation_xyzw) + _COV_0_01
        else:
            orientation = _QUAT.pack(0.0, 0.0, 0.0, 0.0) + _COV_ZERO
        data = b"".join((
            struct.pack("<3I", 0, secs, nsecs), self._frame, orientation,
            _VEC3.pack(*gyro), _COV_0_01, _VEC3.pack(*accel), _COV_0_01))
        return WireMessage(Imu, data)


_COV36_ZERO = struct.pack("<36d", *([0.0] * 36))


class OdometryWire:
    """``nav_msgs/Odometry`` of a planar robot (pose x, y, yaw; twist v, w); no covariance."""

    def __init__(self, frame_id: str, child_frame_id: str):
        self._frame = _string(frame_id)
        self._child = _string(child_frame_id)

    def pack(self, secs, nsecs, x, y, yaw, v, w) -> WireMessage:
        half = 0.5 * yaw
        data = b"".join((
            struct.pack("<3I", 0, secs, nsecs), self._frame, self._child,
            struct.pack("<7d", x, y, 0.0, 0.0, 0.0, math.sin(half), math.cos(half)), _COV36_ZERO,
            struct.pack("<6d", v, 0.0, 0.0, 0.0, 0.0, w), _COV36_ZERO))
        return WireMessage(Odometry, data)


class TransformBatchWire:
    """One ``tf2_msgs/TFMessage`` holding a fixed list of (parent, child) transforms.

    The strings are laid out once; each step only the stamps, translations and rotations are
    written, with numpy, into their byte offsets.
    """

    def __init__(self, frames):
        parts, stamp_offsets, pose_offsets = [struct.pack("<I", len(frames))], [], []
        offset = 4
        for parent, child in frames:
            stamp_offsets.append(offset + 4)
            head = struct.pack("<3I", 0, 0, 0) + _string(parent) + _string(child)
            parts.append(head)
            offset += len(head)
            pose_offsets.append(offset)
            parts.append(bytes(56))
            offset += 56
        self._template = np.frombuffer(b"".join(parts), dtype=np.uint8).copy()
        self._stamp_index = np.asarray(stamp_offsets)[:, None] + np.arange(8)
        self._pose_index = np.asarray(pose_offsets)[:, None] + np.arange(56)
        self.size = len(frames)

    def pack(self, secs: int, nsecs: int, translations, rotations_xyzw) -> WireMessage:
        """``translations`` (M,3) and ``rotations_xyzw`` (M,4) in the order of ``frames``."""
        buf = self._template.copy()
        stamp = np.frombuffer(struct.pack("<2I", secs, nsecs), dtype=np.uint8)
        buf[self._stamp_index] = stamp
        poses = np.empty((self.size, 7), dtype="<f8")
        poses[:, :3] = translations
        poses[:, 3:] = rotations_xyzw
        buf[self._pose_index] = poses.view(np.uint8).reshape(self.size, 56)
        return WireMessage(TFMessage, buf.tobytes())

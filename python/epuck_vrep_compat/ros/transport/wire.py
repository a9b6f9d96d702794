"""Pre-serialised ROS 1 messages for the per-step publishing path.

A step of a many-robot simulation publishes thousands of small messages; building genpy objects
and serialising them field by field costs more than the physics. The messages published every
step have fixed strings (frame ids), so a :class:`MessageBatch` lays out all M messages of one
kind once, as TCPROS frames, and each step only writes the numeric fields into their byte
offsets with numpy. ``test/unit/test_wire.py`` checks every layout byte for byte against genpy.
"""
import struct

import numpy as np
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, Range
from tf2_msgs.msg import TFMessage

_U32 = struct.Struct("<I")


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
    return _U32.pack(len(b)) + b


def _header(frame_id: str) -> bytes:
    return struct.pack("<3I", 0, 0, 0) + _string(frame_id)


class MessageBatch:
    """M messages of one type, each a TCPROS frame (4-byte length, then the body).

    ``fields`` maps a name to (offset of the field in each body, numpy dtype, count); ``pack``
    writes this step's values, shape (M, count), and returns the bytes of all M frames, whose
    frame i is ``data[starts[i]:ends[i]]``.
    """

    def __init__(self, msg_class, bodies, fields):
        self.msg_class = msg_class
        frames = [_U32.pack(len(b)) + b for b in bodies]
        lengths = np.array([len(f) for f in frames])
        self.ends = np.cumsum(lengths)
        self.starts = self.ends - lengths
        self._bounds = list(zip(self.starts.tolist(), self.ends.tolist()))
        self._buffer = np.frombuffer(b"".join(frames), dtype=np.uint8).copy()
        body_starts = self.starts + 4
        self._stamp_index = (body_starts + 4)[:, None] + np.arange(8)
        self._fields = {}
        for name, (offsets, dtype, count) in fields.items():
            width = np.dtype(dtype).itemsize * count
            index = (body_starts + np.asarray(offsets))[:, None] + np.arange(width)
            self._fields[name] = (index, np.dtype(dtype), count)
        self.size = len(bodies)

    def pack(self, secs: int, nsecs: int, **values) -> bytes:
        """The M frames with this stamp and these values (every field, each (M, count))."""
        return self.pack_view(secs, nsecs, **values).tobytes()

    def pack_view(self, secs: int, nsecs: int, **values) -> np.ndarray:
        """As :meth:`pack`, in the batch's own buffer (uint8, read-only), valid until the next
        pack: for a caller that copies what it needs at once (``StepBatch.add_slices``). No
        allocation of the whole step: at 1000 robots, fresh buffers of half a megabyte each
        step cost more in page faults than the packing itself."""
        buf = self._buffer
        buf.flags.writeable = True
        buf[self._stamp_index] = np.frombuffer(struct.pack("<2I", secs, nsecs), dtype=np.uint8)
        for name, array in values.items():
            index, dtype, count = self._fields[name]
            data = np.ascontiguousarray(np.asarray(array).reshape(self.size, count), dtype=dtype)
            buf[index] = data.view(np.uint8).reshape(self.size, -1)
        buf.flags.writeable = False
        return buf

    def bounds(self, i: int):
        """(start, end) of frame i in the bytes ``pack`` returns."""
        return self._bounds[i]

    def frame(self, data: bytes, i: int) -> bytes:
        start, end = self._bounds[i]
        return data[start:end]


def range_batch(frame_ids, radiation_type, field_of_view, min_range, max_range):
    """``sensor_msgs/Range`` with fixed frame, radiation type and limits; field ``range``."""
    tail = struct.pack("<B4f", radiation_type, field_of_view, min_range, max_range, 0.0)
    bodies = [_header(f) + tail for f in frame_ids]
    return MessageBatch(Range, bodies, {"range": ([len(b) - 4 for b in bodies], "<f4", 1)})


_NO_ESTIMATE = struct.pack("<9d", -1.0, 0, 0, 0, 0, 0, 0, 0, 0)


def _diagonal(variances) -> bytes:
    """A 3x3 covariance: diagonal variances, or None for "no estimate" (element 0 = -1)."""
    if variances is None:
        return _NO_ESTIMATE
    x, y, z = (float(v) for v in variances)
    return struct.pack("<9d", x, 0, 0, 0, y, 0, 0, 0, z)


def imu_batch(frame_ids, accel_variance, gyro_variance):
    """``sensor_msgs/Imu`` by its definition and REP 145: no orientation estimate (identity
    quaternion, ``orientation_covariance[0] = -1``), the acceleration's and angular velocity's
    covariances diagonal with the noise model's variances (per axis; all zero, "unknown", when
    the noise is off), ``gyro_variance`` None for a robot without a gyroscope (angular velocity
    covariance[0] = -1); fields ``gyro`` and ``accel`` (3 each)."""
    identity = struct.pack("<4d", 0.0, 0.0, 0.0, 1.0)
    tail = (identity + _NO_ESTIMATE + bytes(24) + _diagonal(gyro_variance) + bytes(24)
            + _diagonal(accel_variance))
    bodies = [_header(f) + tail for f in frame_ids]
    head = [len(_header(f)) for f in frame_ids]
    return MessageBatch(Imu, bodies, {
        "gyro": ([h + 104 for h in head], "<f8", 3),
        "accel": ([h + 200 for h in head], "<f8", 3)})


def odometry_batch(frame_id, child_frame_ids, pose_variances=None):
    """``nav_msgs/Odometry`` of planar robots; fields ``xy`` (2), ``qzw`` (2, the yaw
    quaternion's z and w), ``v`` and ``w`` (1 each). The pose covariance is zero, or diagonal
    with ``pose_variances`` (6: x, y, z, roll, pitch, yaw); the twist's is zero."""
    pose_covariance = (bytes(288) if pose_variances is None else
                       np.diag(np.asarray(pose_variances, dtype="<f8")).tobytes())
    bodies, positions = [], []
    for child in child_frame_ids:
        head = _header(frame_id) + _string(child)
        positions.append(len(head))
        bodies.append(head + struct.pack("<7d", 0, 0, 0, 0, 0, 0, 1.0) + pose_covariance
                      + bytes(48) + bytes(288))
    twist = [p + 56 + 288 for p in positions]
    return MessageBatch(Odometry, bodies, {
        "xy": (positions, "<f8", 2),
        "qzw": ([p + 40 for p in positions], "<f8", 2),
        "v": (twist, "<f8", 1),
        "w": ([t + 40 for t in twist], "<f8", 1)})


def planar_odometry_values(x, y, yaw, v, w):
    """Field values of :func:`odometry_batch` from arrays of planar poses and speeds."""
    half = 0.5 * np.asarray(yaw, dtype=float)
    return dict(xy=np.stack((x, y), axis=-1), qzw=np.stack((np.sin(half), np.cos(half)), -1),
                v=np.asarray(v, dtype=float), w=np.asarray(w, dtype=float))


class TransformBatchWire:
    """One ``tf2_msgs/TFMessage`` holding a fixed list of (parent, child) transforms.

    The strings are laid out once; each step only the stamps, translations and rotations are
    written, with numpy, into their byte offsets.
    """

    def __init__(self, frames):
        parts, stamp_offsets, pose_offsets = [_U32.pack(len(frames))], [], []
        offset = 8                       # after the frame's length and the list's
        for parent, child in frames:
            stamp_offsets.append(offset + 4)
            head = struct.pack("<3I", 0, 0, 0) + _string(parent) + _string(child)
            parts.append(head)
            offset += len(head)
            pose_offsets.append(offset)
            parts.append(bytes(56))
            offset += 56
        body = b"".join(parts)
        self._buffer = np.frombuffer(_U32.pack(len(body)) + body, dtype=np.uint8).copy()
        self._stamp_index = np.asarray(stamp_offsets)[:, None] + np.arange(8)
        self._pose_index = np.asarray(pose_offsets)[:, None] + np.arange(56)
        self._poses = np.empty((len(frames), 7), dtype="<f8")
        self.size = len(frames)

    def frame(self, secs: int, nsecs: int, translations, rotations_xyzw) -> bytes:
        """The TCPROS frame (4-byte length, then the body) of this step's message:
        ``translations`` (M,3) and ``rotations_xyzw`` (M,4) in the order of ``frames``."""
        buf = self._buffer
        buf[self._stamp_index] = np.frombuffer(struct.pack("<2I", secs, nsecs), dtype=np.uint8)
        poses = self._poses
        poses[:, :3] = translations
        poses[:, 3:] = rotations_xyzw
        buf[self._pose_index] = poses.view(np.uint8).reshape(self.size, 56)
        return buf.tobytes()

    def pack(self, secs: int, nsecs: int, translations, rotations_xyzw) -> WireMessage:
        """The message itself (pre-serialised), as :meth:`frame` without the length."""
        return WireMessage(TFMessage, self.frame(secs, nsecs, translations, rotations_xyzw)[4:])


class ImageWire:
    """``sensor_msgs/Image`` frames of one camera: frame id, size and encoding laid out once;
    each image writes only its stamp and pixels (top row first, ``is_bigendian`` 0, seq 0)."""

    _STAMP = struct.Struct("<3I")

    def __init__(self, frame_id: str, width: int, height: int, encoding: str):
        channels = {"rgb8": 3, "mono8": 1}[encoding]
        self.data_size = width * height * channels
        self._tail = (_string(frame_id) + struct.pack("<2I", height, width) + _string(encoding)
                      + struct.pack("<BI", 0, width * channels) + _U32.pack(self.data_size))
        self._length = _U32.pack(self._STAMP.size + len(self._tail) + self.data_size)

    def frame(self, secs: int, nsecs: int, pixels) -> bytes:
        """The TCPROS frame (4-byte length, then the body) of one image; ``pixels``: any
        C-contiguous bytes-like object (a numpy image's ``data``)."""
        pixels = memoryview(pixels).cast("B")
        if pixels.nbytes != self.data_size:
            raise ValueError(f"an image of {self.data_size} bytes expected, got {pixels.nbytes}")
        return b"".join((self._length, self._STAMP.pack(0, secs, nsecs), self._tail, pixels))


__all__ = ["ImageWire", "MessageBatch", "TransformBatchWire", "WireMessage", "imu_batch",
           "odometry_batch", "planar_odometry_values", "range_batch"]

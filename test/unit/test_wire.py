"""The pre-serialised layouts must produce exactly genpy's bytes, frame by frame."""
import io
import math
import struct

import numpy as np
import pytest
from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, Imu, Range
from tf2_msgs.msg import TFMessage

from epuck_vrep_compat.ros.transport import wire


def _framed(msg):
    buff = io.BytesIO()
    msg.serialize(buff)
    body = buff.getvalue()
    return struct.pack("<I", len(body)) + body


def _stamp(msg, secs, nsecs, frame_id):
    msg.header.stamp.secs, msg.header.stamp.nsecs = secs, nsecs
    msg.header.frame_id = frame_id
    return msg


def test_range_batch_matches_genpy():
    frames = ["ePuck3/base_prox5", "ePuck12/base_prox0", "x"]
    batch = wire.range_batch(frames, Range.INFRARED, 0.52359878, 0.0015, 0.05)
    values = np.array([0.0321, 0.05, 0.0015])
    data = batch.pack(12, 500000000, range=values)
    for i, (frame, value) in enumerate(zip(frames, values)):
        msg = _stamp(Range(radiation_type=Range.INFRARED, field_of_view=0.52359878,
                           min_range=0.0015, max_range=0.05, range=value), 12, 500000000, frame)
        assert batch.frame(data, i) == _framed(msg)
    assert batch.msg_class._md5sum == Range._md5sum
    # the view is the batch's own buffer, rewritten by the next pack; pack's bytes stay
    view = batch.pack_view(12, 500000000, range=values)
    assert bytes(view) == data and not view.flags.writeable
    batch.pack_view(13, 0, range=values[::-1])
    assert bytes(view) != data
    assert batch.pack(12, 500000000, range=values) == data


def test_imu_batch_matches_genpy_and_rep_145():
    accel = np.array([[0.1, -0.2, 9.81], [1.0, 2.0, 3.0]])
    gyro = np.array([[0.0, 0.0, 0.5], [-1.0, 0.25, 0.0]])
    frames = ["ePuck0/base_link", "epuck_robot_11/base_link"]
    accel_var = [0.03559 ** 2, 0.03079 ** 2, 0.0493 ** 2]
    for gyro_var in ([0.005 ** 2] * 3, None):
        batch = wire.imu_batch(frames, accel_var, gyro_var)
        data = batch.pack(3, 7, accel=accel, gyro=gyro)
        for i, frame in enumerate(frames):
            msg = _stamp(Imu(), 3, 7, frame)
            (msg.linear_acceleration.x, msg.linear_acceleration.y,
             msg.linear_acceleration.z) = accel[i]
            msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z = gyro[i]
            msg.orientation.w = 1.0
            msg.orientation_covariance = [-1.0, 0, 0, 0, 0, 0, 0, 0, 0]   # no estimate
            msg.linear_acceleration_covariance = [accel_var[0], 0, 0, 0, accel_var[1], 0,
                                                  0, 0, accel_var[2]]
            if gyro_var is None:
                msg.angular_velocity_covariance = [-1.0, 0, 0, 0, 0, 0, 0, 0, 0]
            else:
                msg.angular_velocity_covariance = [gyro_var[0], 0, 0, 0, gyro_var[1], 0,
                                                   0, 0, gyro_var[2]]
            assert batch.frame(data, i) == _framed(msg)


@pytest.mark.parametrize("variances", [None, (0.001, 0.001, 1000.0, 1000.0, 1000.0, 0.001)])
def test_odometry_batch_matches_genpy(variances):
    children = ["epuck_robot_1/base_link", "ePuck0/base_link"]
    batch = wire.odometry_batch("odom", children, variances)
    x, y, yaw = np.array([0.3, -1.0]), np.array([-0.4, 2.0]), np.array([1.2, -3.0])
    v, w = np.array([0.05, 0.0]), np.array([-0.3, 1.5])
    data = batch.pack(100, 0, **wire.planar_odometry_values(x, y, yaw, v, w))
    for i, child in enumerate(children):
        msg = _stamp(Odometry(), 100, 0, "odom")
        msg.child_frame_id = child
        msg.pose.pose.position.x, msg.pose.pose.position.y = x[i], y[i]
        msg.pose.pose.orientation.z = np.sin(0.5 * yaw[i])
        msg.pose.pose.orientation.w = np.cos(0.5 * yaw[i])
        msg.twist.twist.linear.x, msg.twist.twist.angular.z = v[i], w[i]
        if variances is not None:
            msg.pose.covariance = np.diag(variances).ravel().tolist()
        assert batch.frame(data, i) == _framed(msg)
        assert abs(msg.pose.pose.orientation.z - math.sin(0.5 * yaw[i])) < 1e-15


def test_transform_batch_matches_genpy():
    frames = [("odom", "ePuck0/base_link"), ("ePuck0/base_link", "ePuck0/base_prox0"),
              ("odom", "ePuck12/base_link")]
    rng = np.random.default_rng(1)
    t = rng.normal(size=(3, 3))
    q = rng.normal(size=(3, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    msg = TFMessage()
    for (parent, child), ti, qi in zip(frames, t, q):
        ts = TransformStamped()
        ts.header.stamp.secs, ts.header.stamp.nsecs = 42, 50000000
        ts.header.frame_id, ts.child_frame_id = parent, child
        ts.transform.translation.x, ts.transform.translation.y, ts.transform.translation.z = ti
        (ts.transform.rotation.x, ts.transform.rotation.y, ts.transform.rotation.z,
         ts.transform.rotation.w) = qi
        msg.transforms.append(ts)
    layout = wire.TransformBatchWire(frames)
    packed = layout.pack(42, 50000000, t, q)
    assert packed._md5sum == TFMessage._md5sum
    assert _framed(packed)[4:] == _framed(msg)[4:]
    assert layout.frame(42, 50000000, t, q) == _framed(msg)


@pytest.mark.parametrize("encoding,channels", [("rgb8", 3), ("mono8", 1)])
def test_image_wire_matches_genpy(encoding, channels):
    layout = wire.ImageWire("ePuck4/camera_optical", 5, 3, encoding)
    pixels = bytes(range(5 * 3 * channels))
    msg = _stamp(Image(height=3, width=5, encoding=encoding, is_bigendian=0, step=5 * channels,
                       data=pixels), 7, 250, "ePuck4/camera_optical")
    assert layout.frame(7, 250, pixels) == _framed(msg)
    image = np.frombuffer(pixels, dtype=np.uint8).reshape((3, 5, channels)[:2 + (channels > 1)])
    assert layout.frame(7, 250, image.data) == _framed(msg)     # a numpy image, uncopied
    with pytest.raises(ValueError):
        layout.frame(7, 250, pixels[:-1])

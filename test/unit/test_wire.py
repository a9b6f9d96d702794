"""The pre-serialised encoders must produce exactly genpy's bytes."""
import io
import math

import numpy as np
from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, Range
from tf2_msgs.msg import TFMessage

from epuck_vrep_compat.ros.wire import ImuWire, OdometryWire, RangeWire, TransformBatchWire


def _genpy_bytes(msg):
    buff = io.BytesIO()
    msg.serialize(buff)
    return buff.getvalue()


def _wire_bytes(wire_msg):
    buff = io.BytesIO()
    wire_msg.serialize(buff)
    return buff.getvalue()


def test_range_matches_genpy():
    msg = Range(radiation_type=Range.INFRARED, field_of_view=0.52359878, min_range=0.0015,
                max_range=0.05, range=0.0321)
    msg.header.stamp.secs, msg.header.stamp.nsecs = 12, 500000000
    msg.header.frame_id = "ePuck3/base_prox5"
    wire = RangeWire("ePuck3/base_prox5", Range.INFRARED, 0.52359878, 0.0015, 0.05)
    packed = wire.pack(12, 500000000, 0.0321)
    assert packed._md5sum == Range._md5sum
    assert _wire_bytes(packed) == _genpy_bytes(msg)


def test_imu_matches_genpy_both_conventions():
    for known in (False, True):
        msg = Imu()
        msg.header.stamp.secs, msg.header.stamp.nsecs = 3, 7
        msg.header.frame_id = "ePuck0/base_link"
        msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z = 0.1, -0.2, 9.81
        msg.angular_velocity.z = 0.5
        msg.linear_acceleration_covariance = [0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01]
        msg.angular_velocity_covariance = [0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01]
        if known:
            msg.orientation.w = 1.0
            msg.orientation_covariance = [0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01]
        else:
            msg.orientation.w = 0.0
        wire = ImuWire("ePuck0/base_link", orientation_known=known)
        packed = wire.pack(3, 7, (0.1, -0.2, 9.81), (0.0, 0.0, 0.5))
        assert _wire_bytes(packed) == _genpy_bytes(msg)


def test_odometry_matches_genpy():
    msg = Odometry()
    msg.header.stamp.secs = 100
    msg.header.frame_id = "odom"
    msg.child_frame_id = "epuck_robot_1/base_link"
    yaw = 1.2
    msg.pose.pose.position.x, msg.pose.pose.position.y = 0.3, -0.4
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = 0.05, -0.3
    packed = OdometryWire("odom", "epuck_robot_1/base_link").pack(100, 0, 0.3, -0.4, yaw, 0.05, -0.3)
    assert _wire_bytes(packed) == _genpy_bytes(msg)


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
    packed = TransformBatchWire(frames).pack(42, 50000000, t, q)
    assert packed._md5sum == TFMessage._md5sum
    assert _wire_bytes(packed) == _genpy_bytes(msg)

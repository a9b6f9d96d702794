"""Message builders of the driver topics beyond the shared ones, field for field as GCtronic's
drivers fill them (``epuck2_driver_cpp.cpp``; ``epuck_driver_cpp.cpp`` for the e-puck 1's
``floor``, ``microphone`` and ``motor_speed``). Pure functions of one robot's readings.
"""
import math

import numpy as np
from geometry_msgs.msg import Point, Quaternion
from sensor_msgs.msg import BatteryState, Imu, MagneticField, Range
from visualization_msgs.msg import Marker

from epuck_vrep_compat.geometry.transforms import quat_from_rpy

_DRIVER_COVARIANCE = (0.01, 0.0, 0.0, 0.0, 0.01, 0.0, 0.0, 0.0, 0.01)
DIST_SENS_FOV_RAD = 0.43        # "about 25 degrees (+/- 12.5)"
DIST_SENS_MIN_M = 0.005
DIST_SENS_MAX_M = 2.0
BATTERY_MIN_V = 3.4             # the driver's MIN_VOLTAGE, MAX_VOLTAGE
BATTERY_MAX_V = 4.2


def _header(msg, stamp, frame):
    """Frame id, and the stamp unless None (a template laid out once, stamped per step)."""
    msg.header.frame_id = frame
    if stamp is not None:
        msg.header.stamp = stamp


def tilt_quat(accel):
    """x, y, z, w (..., 4) of the tilt an accelerometer reads (aerospace Rxyz): roll =
    atan2(a_y, a_z), pitch = atan2(-a_x, |a_yz|), yaw 0; one reading or (N, 3)."""
    a = np.asarray(accel, dtype=float)
    roll = np.arctan2(a[..., 1], a[..., 2])
    pitch = np.arctan2(-a[..., 0], np.hypot(a[..., 1], a[..., 2]))
    return quat_from_rpy(roll, pitch, 0.0)


def imu(stamp, frame, accel, gyro) -> Imu:
    """The e-puck2's Imu: roll and pitch from the accelerometer (aerospace Rxyz), yaw 0, and
    the driver's covariances (diag 0.01 for all three)."""
    msg = Imu()
    _header(msg, stamp, frame)
    ax, ay, az = (float(v) for v in accel)
    msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z = ax, ay, az
    gx, gy, gz = (float(v) for v in gyro)
    msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z = gx, gy, gz
    msg.orientation = Quaternion(*(float(v) for v in tilt_quat((ax, ay, az))))
    msg.orientation_covariance = _DRIVER_COVARIANCE
    msg.angular_velocity_covariance = _DRIVER_COVARIANCE
    msg.linear_acceleration_covariance = _DRIVER_COVARIANCE
    return msg


def dist_sens(stamp, frame, range_m) -> Range:
    msg = Range(radiation_type=Range.INFRARED, field_of_view=DIST_SENS_FOV_RAD,
                min_range=DIST_SENS_MIN_M, max_range=DIST_SENS_MAX_M,
                range=min(max(float(range_m), DIST_SENS_MIN_M), DIST_SENS_MAX_M))
    _header(msg, stamp, frame)
    return msg


def mag_field(stamp, frame, field_tesla) -> MagneticField:
    msg = MagneticField()
    _header(msg, stamp, frame)
    msg.magnetic_field.x, msg.magnetic_field.y, msg.magnetic_field.z = (
        float(v) for v in field_tesla)
    msg.magnetic_field_covariance = (0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01)
    return msg


def mag_field_vector(stamp, frame, field_tesla) -> Marker:
    """The driver's yellow arrow from the origin to the field's horizontal direction (1 m)."""
    msg = Marker(type=Marker.ARROW)
    _header(msg, stamp, frame)
    msg.pose.orientation.w = 1.0
    bx, by = float(field_tesla[0]), float(field_tesla[1])
    mod = math.hypot(bx, by) or 1.0
    msg.points = [Point(0.0, 0.0, 0.0), Point(bx / mod, by / mod, 0.0)]
    msg.scale.x, msg.scale.y, msg.scale.z = 0.002, 0.003, 0.005
    msg.color.r, msg.color.g, msg.color.b, msg.color.a = 1.0, 1.0, 0.0, 1.0
    return msg


def battery(stamp, frame, voltage) -> BatteryState:
    msg = BatteryState(voltage=float(voltage), present=True)
    msg.percentage = (msg.voltage - BATTERY_MIN_V) / (BATTERY_MAX_V - BATTERY_MIN_V)
    _header(msg, stamp, frame)
    return msg


def text_marker(stamp, frame, label, values, z) -> Marker:
    """The drivers' white text above the robot: ``"<label>: [a, b, c]"``, at (0.15, 0, z)."""
    msg = Marker(type=Marker.TEXT_VIEW_FACING)
    _header(msg, stamp, frame)
    msg.pose.position.x, msg.pose.position.z = 0.15, z
    msg.pose.orientation.w = 1.0
    msg.scale.z = 0.01
    msg.color.r = msg.color.g = msg.color.b = msg.color.a = 1.0
    msg.text = f"{label}: [" + ", ".join(str(int(v)) for v in values) + "]"
    return msg


def floor(stamp, frame, values) -> Marker:
    return text_marker(stamp, frame, "floor", values, 0.13)


def microphone(stamp, frame, values) -> Marker:
    return text_marker(stamp, frame, "mic", values, 0.11)


def motor_speed(stamp, frame, values) -> Marker:
    return text_marker(stamp, frame, "speed", values, 0.15)

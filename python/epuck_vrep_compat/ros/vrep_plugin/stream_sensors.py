"""The legacy plugin's sensor publisher streams: vision sensor image, info, depth buffer, depth
cloud and read (image statistics), proximity sensor, laser scanner and range finder signals,
odometry and twist (V-REP 3.3.0's ``ROS_server::streamAllData``, ``streamVisionSensorImage``,
``streamLaserCloud``, ``streamDepthSensorCloud``). See :mod:`stream_publishers` for the
contract of a :class:`PublisherKind`.

Depth cloud (organised, resX x resY, V-REP's row order: bottom row first), per pixel (i, j):
  depth = near + (far - near) * buffer[j, i]       [m, along the sensor's z axis]
  x = -(i - resX / 2) / f * depth,  y = (j - resY / 2) / f * depth,  z = depth
  f = (resX / 2) / tan(perspective_angle / 2)      [px]
  rgb = uint32 0x00RRGGBB of the pixel
"""
import math

import numpy as np
from geometry_msgs.msg import Point32, TwistStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, Image, LaserScan, PointCloud2, PointField
from std_msgs.msg import Int32
from vrep_common.msg import ProximitySensorData, VisionSensorData, VisionSensorDepthBuff

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.frames import WORLD_FRAME
from epuck_vrep_compat.geometry.transforms import quat_conj, quat_rotate
from epuck_vrep_compat.ros.messages import fill_image, pinhole_camera_info
from epuck_vrep_compat.ros.vrep_plugin.stream_publishers import (
    PublisherKind, set_header, packed_floats, string_signal)
from epuck_vrep_compat.vrep.backend import VrepError

# The plugin's fixed LaserScan fields (George Moustris' stream)
LASER_TIME_INCREMENT_S = 0.0000173611115315
LASER_SCAN_TIME_S = 0.025
LASER_RANGE_MIN_M = 0.023
LASER_RANGE_MAX_M = 60.0
COVARIANCE_FLOATS = 72          # odometry: pose covariance (36) then twist covariance (36)
TWIST_FLOATS = 6

_XYZ_FIELDS = [PointField(name, offset, PointField.FLOAT32, 1)
               for name, offset in (("x", 0), ("y", 4), ("z", 8))]
_XYZ_RGB_FIELDS = _XYZ_FIELDS + [PointField("rgb", 12, PointField.UINT32, 1)]
_CLOUD_DTYPE = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4")])


def _check_vision(backend, aux):
    backend.vision(aux.int1)


def _image(step, aux):
    rgb = step.backend.vision_image(aux.int1, mono=False)     # top row first, as ROS
    msg = fill_image(Image(), rgb)
    set_header(msg.header, step, step.object_frame(aux.int1))
    return msg


def _camera_info(step, aux):
    backend = step.backend
    width, height = backend.vision(aux.int1).resolution
    angle = backend.object_float_parameter(aux.int1, vc.VISIONFLOATPARAM_PERSPECTIVE_ANGLE)
    f = (width / 2.0) / math.tan(angle / 2.0)
    # V-REP's formula: focal length from the perspective angle over the width, integer centre
    msg = pinhole_camera_info(width, height, f, width // 2, height // 2)
    set_header(msg.header, step, step.object_frame(aux.int1))
    return msg


def _depth_buffer(step, aux):
    (width, height), buffer = step.backend.vision_depth(aux.int1)
    msg = VisionSensorDepthBuff()
    msg.x, msg.y = Int32(width), Int32(height)
    msg.data.data = buffer.ravel().tolist()
    return msg


def _depth_cloud(step, aux):
    backend = step.backend
    sensor = backend.vision(aux.int1)
    (width, height), buffer = backend.vision_depth(aux.int1)       # bottom row first
    rgb = backend.vision_image(aux.int1, mono=False)[::-1]         # to V-REP's row order
    angle = backend.object_float_parameter(aux.int1, vc.VISIONFLOATPARAM_PERSPECTIVE_ANGLE)
    near, far = np.float32(sensor.spec.near_m), np.float32(sensor.spec.far_m)
    f = np.float32((width / 2.0) / math.tan(angle / 2.0))
    depth = near + (far - near) * buffer
    points = np.empty((height, width), dtype=_CLOUD_DTYPE)
    points["x"] = depth * (-(np.arange(width, dtype=np.float32) - width / 2.0) / f)[None, :]
    points["y"] = depth * ((np.arange(height, dtype=np.float32) - height / 2.0) / f)[:, None]
    points["z"] = depth
    rgb = rgb.astype(np.uint32)
    points["rgb"] = (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]
    msg = PointCloud2()
    set_header(msg.header, step, step.object_frame(aux.int1))
    msg.height, msg.width = height, width
    msg.fields = _XYZ_RGB_FIELDS
    msg.is_bigendian = False
    msg.point_step = _CLOUD_DTYPE.itemsize
    msg.row_step = width * msg.point_step
    msg.data = points.tobytes()
    msg.is_dense = True
    return msg


def _read_vision_sensor(step, aux):
    state, packets = step.backend.read_vision_sensor(aux.int1)
    msg = VisionSensorData()
    msg.triggerState = Int32(int(state))
    msg.packetData.data = [float(v) for packet in packets for v in packet]
    msg.packetSizes.data = [len(packet) for packet in packets]
    return msg


def _check_proximity(backend, aux):
    backend.proximity(aux.int1)


def _proximity(step, aux):
    state, point, handle, normal = step.backend.proximity(aux.int1)
    if state <= 0:
        return None                          # published only while something is detected
    return ProximitySensorData(detectedPoint=Point32(*(float(v) for v in point)),
                               detectedObject=Int32(int(handle)),
                               normalVector=Point32(*(float(v) for v in normal)))


def _laser_scan(step, aux):
    frame_id = step.object_frame(aux.int1)   # the frame object must exist
    data = string_signal(step.backend, aux.string)
    values = packed_floats(data) if data is not None else ()
    if len(values) <= 3:
        return None
    msg = LaserScan()
    set_header(msg.header, step, frame_id, step.seq)
    msg.angle_min, msg.angle_max, msg.angle_increment = values[-3:]
    msg.time_increment = LASER_TIME_INCREMENT_S
    msg.scan_time = LASER_SCAN_TIME_S
    msg.range_min, msg.range_max = LASER_RANGE_MIN_M, LASER_RANGE_MAX_M
    msg.ranges = list(values[:-3])
    return msg


def _range_finder(step, aux):
    data = string_signal(step.backend, aux.string)
    if data is None:
        return None
    try:
        frame_id = step.object_frame(aux.int1)
    except VrepError:
        frame_id = ""                        # the plugin never ends this stream
    count = len(data) // 12
    msg = PointCloud2()
    set_header(msg.header, step, frame_id)
    msg.height, msg.width = 1, count
    msg.fields = _XYZ_FIELDS
    msg.is_bigendian = False
    msg.point_step = 12
    msg.row_step = 12 * count
    msg.data = data
    msg.is_dense = True
    return msg


def _odometry(step, aux):
    backend = step.backend
    child_frame = step.object_frame(aux.int1)
    reference = backend.parent(aux.int1) if aux.int2 == vc.HANDLE_PARENT else aux.int2
    reference_name = WORLD_FRAME
    if reference != vc.WORLD:
        try:
            reference_name = backend.object_name(reference)
        except VrepError:
            reference = vc.WORLD
    msg = Odometry()
    set_header(msg.header, step, step.frames.frame_id(reference_name), step.seq)
    msg.child_frame_id = child_frame
    position, quat = backend.pose(aux.int1, reference)
    linear, angular = backend.velocity(aux.int1)
    if reference != vc.WORLD:
        # The twist in the reference's axes (the plugin also translated the linear velocity
        # as if it were a point; that slip is not reproduced).
        to_reference = quat_conj(backend.pose(reference)[1])
        linear, angular = quat_rotate(to_reference, linear), quat_rotate(to_reference, angular)
    pose, twist = msg.pose.pose, msg.twist.twist
    pose.position.x, pose.position.y, pose.position.z = (float(v) for v in position)
    o = pose.orientation
    o.x, o.y, o.z, o.w = (float(v) for v in quat)
    twist.linear.x, twist.linear.y, twist.linear.z = (float(v) for v in linear)
    twist.angular.x, twist.angular.y, twist.angular.z = (float(v) for v in angular)
    data = string_signal(backend, aux.string)
    if data is not None:
        values = packed_floats(data)
        if len(values) != COVARIANCE_FLOATS:
            return None                      # the plugin skips the message
        msg.pose.covariance = [float(v) for v in values[:36]]
        msg.twist.covariance = [float(v) for v in values[36:]]
    return msg


def _twist(step, aux):
    backend = step.backend
    if aux.string:
        data = string_signal(backend, aux.string)
        values = packed_floats(data) if data is not None else ()
        if data is None or len(data) != 4 * TWIST_FLOATS:
            raise VrepError(f"string signal '{aux.string}' does not hold {TWIST_FLOATS} floats")
        linear, angular = values[:3], values[3:]
    else:
        linear, angular = backend.velocity(aux.int1)
    msg = TwistStamped()
    set_header(msg.header, step, step.object_frame(aux.int1))
    t = msg.twist
    t.linear.x, t.linear.y, t.linear.z = (float(v) for v in linear)
    t.angular.x, t.angular.y, t.angular.z = (float(v) for v in angular)
    return msg


SENSOR_PUBLISHERS = {
    vc.STRMCMD_GET_VISION_SENSOR_IMAGE: PublisherKind(
        "get_vision_sensor_image", Image, _image, check=_check_vision, probe=_check_vision),
    vc.STRMCMD_GET_VISION_SENSOR_INFO: PublisherKind(
        "get_vision_sensor_info", CameraInfo, _camera_info, check=_check_vision),
    vc.STRMCMD_GET_VISION_SENSOR_DEPTH_BUFFER: PublisherKind(
        "get_vision_sensor_depth_buffer", VisionSensorDepthBuff, _depth_buffer,
        check=_check_vision, probe=_check_vision),
    vc.STRMCMD_GET_DEPTH_SENSOR_DATA: PublisherKind(
        "get_depth_sensor_data", PointCloud2, _depth_cloud, check=_check_vision,
        probe=_check_vision),
    vc.STRMCMD_READ_VISION_SENSOR: PublisherKind(
        "read_vision_sensor", VisionSensorData, _read_vision_sensor, check=_check_vision,
        probe=_check_vision),
    vc.STRMCMD_READ_PROXIMITY_SENSOR: PublisherKind(
        "read_proximity_sensor", ProximitySensorData, _proximity, check=_check_proximity),
    vc.STRMCMD_GET_LASER_SCANNER_DATA: PublisherKind(
        "get_laser_scanner_data", LaserScan, _laser_scan),
    vc.STRMCMD_GET_RANGE_FINDER_DATA: PublisherKind(
        "get_range_finder_data", PointCloud2, _range_finder),
    vc.STRMCMD_GET_ODOM_DATA: PublisherKind("get_odom_data", Odometry, _odometry),
    vc.STRMCMD_GET_TWIST_STATUS: PublisherKind("get_twist_status", TwistStamped, _twist),
}

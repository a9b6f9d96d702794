"""Message builders more than one face uses: stamps, images, camera infos, rviz markers."""
import math

import numpy as np
import rospy
from sensor_msgs.msg import CameraInfo, Image
from visualization_msgs.msg import Marker


def time_stamp(time_s: float) -> rospy.Time:
    """The simulation time as a stamp, to the nearest nanosecond. ``rospy.Time.from_sec``
    truncates: step 43 of 50 ms would be 2.149999999 s, and a client's 50 ms timer, due at
    2.150000000 s, would miss that step and fire twice at the next."""
    return rospy.Time(0, int(round(time_s * 1e9)))


def fill_image(msg: Image, pixels) -> Image:
    """Fill ``msg`` with top-row-first pixels: (H, W, 3) as rgb8, (H, W) as mono8."""
    mono = pixels.ndim == 2
    msg.height, msg.width = int(pixels.shape[0]), int(pixels.shape[1])
    msg.encoding = "mono8" if mono else "rgb8"
    msg.is_bigendian = 0
    msg.step = msg.width * (1 if mono else 3)
    msg.data = np.ascontiguousarray(pixels, dtype=np.uint8).tobytes()
    return msg


def pinhole_camera_info(width, height, f, cx, cy, frame_id="") -> CameraInfo:
    """An undistorted pinhole CameraInfo with square pixels (focal length ``f`` in pixels)."""
    info = CameraInfo()
    info.header.frame_id = frame_id
    info.width, info.height = width, height
    info.distortion_model = "plumb_bob"
    info.D = [0.0] * 5
    info.K = [f, 0.0, cx, 0.0, f, cy, 0.0, 0.0, 1.0]
    info.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    info.P = [f, 0.0, cx, 0.0, 0.0, f, cy, 0.0, 0.0, 0.0, 1.0, 0.0]
    return info


def camera_info(width, height, vertical_fov_rad, frame_id) -> CameraInfo:
    """The pinhole CameraInfo of a camera with this vertical field of view, centred."""
    f = 0.5 * height / math.tan(0.5 * vertical_fov_rad)
    return pinhole_camera_info(width, height, f, 0.5 * width, 0.5 * height, frame_id)


def shape_marker(frame, ns, marker_id, shape, position, scale, color, quat=(0, 0, 0, 1)):
    """A frame-locked primitive marker (the pose is relative to ``frame``)."""
    m = Marker()
    m.header.frame_id = frame
    m.ns = ns
    m.id = marker_id
    m.type = shape
    m.action = Marker.ADD
    m.frame_locked = True
    m.pose.position.x, m.pose.position.y, m.pose.position.z = (float(v) for v in position)
    (m.pose.orientation.x, m.pose.orientation.y, m.pose.orientation.z,
     m.pose.orientation.w) = (float(v) for v in quat)
    m.scale.x, m.scale.y, m.scale.z = (float(v) for v in scale)
    m.color = color
    return m

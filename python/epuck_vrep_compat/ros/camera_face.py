"""Each robot's camera: rendered by the core's ray-cast camera, only while someone subscribes.

Unlike the V-REP script (frame id ``"a"``, bottom row first, ``is_bigendian`` 1) the image is
top row first, frame ``<robot>/camera_optical``, with a latched ``camera_info`` beside it.
The image publisher has a queue of 1: a slow viewer drops frames instead of stalling the step.
"""
import math

import numpy as np
import rospy
from sensor_msgs.msg import CameraInfo, Image

from epuck_vrep_compat.ros import names


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
    f = 0.5 * height / math.tan(0.5 * vertical_fov_rad)
    return pinhole_camera_info(width, height, f, 0.5 * width, 0.5 * height, frame_id)


class CameraFace:
    def __init__(self, profile, sim):
        self.sim = sim
        params = sim.camera
        self._period_s = 1.0 / params.rate_hz
        self._next_due_s = np.zeros(sim.size)
        self._sensors = [robot.parts["camera"].properties["vision"] for robot in sim.robots]
        self._frames = [profile.frame(name, names.CAMERA_FRAME) for name in sim.robot_names]
        self._images = [rospy.Publisher(profile.topic(name, "camera"), Image, queue_size=1)
                        for name in sim.robot_names]
        self._infos = []
        for name, frame in zip(sim.robot_names, self._frames):
            pub = rospy.Publisher(profile.topic(name, "camera_info"), CameraInfo, queue_size=1,
                                  latch=True)
            pub.publish(camera_info(params.width, params.height, params.vertical_fov_rad, frame))
            self._infos.append(pub)

    def publish(self, secs: int, nsecs: int):
        now = self.sim.time_s
        for i, pub in enumerate(self._images):
            if now + 1e-9 < self._next_due_s[i] or not pub.impl.has_connections():
                continue
            self._next_due_s[i] = now + self._period_s
            pub.publish(self.render(i, secs, nsecs))

    def render(self, i: int, secs: int, nsecs: int) -> Image:
        rgb, _depth = self._sensors[i].render()
        msg = fill_image(Image(), rgb)
        msg.header.stamp = rospy.Time(secs, nsecs)
        msg.header.frame_id = self._frames[i]
        return msg

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
from epuck_vrep_compat.scene.transforms import quat_from_yaw, quat_rotate


def camera_info(width, height, vertical_fov_rad, frame_id) -> CameraInfo:
    fy = 0.5 * height / math.tan(0.5 * vertical_fov_rad)
    fx = fy                                   # square pixels
    cx, cy = 0.5 * width, 0.5 * height
    info = CameraInfo()
    info.header.frame_id = frame_id
    info.width, info.height = width, height
    info.distortion_model = "plumb_bob"
    info.D = [0.0] * 5
    info.K = [fx, 0, cx, 0, fy, cy, 0, 0, 1]
    info.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    info.P = [fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0]
    return info


class CameraFace:
    def __init__(self, profile, sim, params):
        self.sim = sim
        self.params = params
        self._period_s = 1.0 / params.rate_hz
        self._next_due_s = np.zeros(sim.size)
        camera = sim.robots[0].parts["camera"] if sim.size else None
        self._mount_position = camera.local_position if camera else np.zeros(3)
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
        x, y, yaw = self.sim.swarm.poses[i]
        q_robot = quat_from_yaw(yaw)
        position = np.array([x, y, 0.0]) + quat_rotate(q_robot, self._mount_position)
        p = self.params
        rgb, _depth = self.sim.world.render(position, q_robot, p.width, p.height,
                                            p.vertical_fov_rad, p.near_m, p.far_m,
                                            self.sim.robots[i].root.handle)
        msg = Image()
        msg.header.stamp = rospy.Time(secs, nsecs)
        msg.header.frame_id = self._frames[i]
        msg.height, msg.width = rgb.shape[0], rgb.shape[1]
        msg.encoding = "rgb8"
        msg.is_bigendian = 0
        msg.step = 3 * msg.width
        msg.data = np.ascontiguousarray(rgb, dtype=np.uint8).tobytes()
        return msg




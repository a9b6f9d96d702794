"""[/telecamera_0] and [/telecamera_1] (thesis section 4.3.2): the two Axis 212 PTZ cameras.

Each looks up its vision sensor's handle by name with simRosGetObjectHandle (camera 0 is
``camera0``, camera 1 is ``camera``: the thesis's names), then every cycle reads the image with
simRosGetVisionSensorImage (options 0: rgb8) and republishes it on /Camera_Image_0 or
/Camera_Image_1. The plugin leaves the image's header empty; we stamp it with ROS time
(simulation time under /use_sim_time) and set frame_id to the sensor's name. While nobody
subscribes, the image is not requested (rendering costs the simulator); a missing sensor is
warned about all the same.

Parameters: ``~sensor_name`` (camera0 / camera), ``~rate`` (20 Hz).
"""
from typing import Optional

import rospy
from sensor_msgs.msg import Image
from vrep_common.srv import simRosGetObjectHandle, simRosGetVisionSensorImage

from epuck_vrep_compat.compat.thesis_names import CAMERAS
from epuck_vrep_compat.thesis import params
from epuck_vrep_compat.thesis.vrep_client import VrepClient, run_node, spin_periodic

RGB8 = 0                    # simRosGetVisionSensorImage options: bit 0 clear = rgb8
IMAGE_SERVICES = {"simRosGetObjectHandle": simRosGetObjectHandle,
                  "simRosGetVisionSensorImage": simRosGetVisionSensorImage}


def stamp_header(header, frame_id: str):
    """Fill what the plugin leaves empty: the stamp (now) and the frame (the sensor's name)."""
    if header.stamp.is_zero():
        header.stamp = rospy.get_rostime()
    if not header.frame_id:
        header.frame_id = frame_id


def read_image(client: VrepClient, handle: int, sensor_name: str) -> Optional[Image]:
    """The sensor's rgb8 image, or None (warned, throttled) when it cannot be read."""
    res = client.call("simRosGetVisionSensorImage", handle=handle, options=RGB8)
    if res is None:
        return None
    if res.result == -1:
        client.log.warn("image:" + sensor_name, "%s: simRosGetVisionSensorImage failed for '%s'",
                        rospy.get_name(), sensor_name)
        client.forget_handle(sensor_name)
        return None
    stamp_header(res.image.header, sensor_name)
    return res.image


class CameraNode:
    """One ceiling camera's node: its vision sensor's image from /vrep, republished."""

    def __init__(self, index: int):
        camera = CAMERAS[index]
        self.sensor_name = params.read_name("sensor_name", camera.sensor_name)
        self.rate_hz = params.read_rate_hz()
        self.client = VrepClient(IMAGE_SERVICES)
        self._pub = rospy.Publisher(camera.topic, Image, queue_size=1)     # images: newest only
        rospy.loginfo("%s: vision sensor '%s' -> %s, rate %.1f Hz", rospy.get_name(),
                      self.sensor_name, camera.topic, self.rate_hz)

    def step(self):
        handle = self.client.handle(self.sensor_name, "vision sensor")   # warns while missing
        if handle < 0 or self._pub.get_num_connections() == 0:
            return
        image = read_image(self.client, handle, self.sensor_name)
        if image is not None:
            self._pub.publish(image)

    def run(self):
        spin_periodic(self.rate_hz, self.step)


def main(index: int) -> int:
    return run_node(CAMERAS[index].node, lambda: CameraNode(index))

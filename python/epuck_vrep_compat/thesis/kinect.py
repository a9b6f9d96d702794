"""[/kinect] (thesis section 4.3.3): the Kinect's depth and colour.

The depth sensor ``kinect_depth`` is read with simRosGetVisionSensorDepthBuffer every cycle and
published twice:
- /kinect/depth_buffer (std_msgs/Float32MultiArray): the buffer as V-REP gives it, values 0..1
  between the near and far clipping planes (0 nearest), rows bottom-up as in V-REP's buffer;
  layout dims ("height", resY) then ("width", resX);
- /kinect/depth/image (sensor_msgs/Image 32FC1, REP 118): depth in metres,
  near + (far - near) * value, rows top-down as every ROS image; +Inf where nothing is nearer
  than the far plane (value 1).
The colour sensor ``kinect_rgb`` is read with simRosGetVisionSensorImage and published on
/kinect/rgb/image (rgb8). Topics follow openni_launch's ``camera/depth/image`` and
``camera/rgb/...`` layout under ``/kinect``. Nothing is requested for a topic nobody subscribes.

The clipping planes are parameters, Kinect v1's usable range by default (0.5 .. 5.0 m, see
spec/models.md section 6); they must match the scene's sensor: at start-up the sensor's own
planes are read (simRosGetObjectFloatParameter 1000/1001) and a mismatch is warned about.

Parameters: ``~depth_sensor`` (kinect_depth), ``~rgb_sensor`` (kinect_rgb),
``~near_clipping_m`` (0.5), ``~far_clipping_m`` (5.0), ``~rate`` (20 Hz), ``~lockstep``
(false). The node reads at ``~rate`` of ROS time; with ``~lockstep``, at the simulation steps
instead (each new ``/clock`` time): at each step whose time passes a multiple of 1/``~rate``,
stamped with the step's time, so that a reader in lock-step (``operator_tracker``'s
``~kinect_period_s``, the same rule: ``nodes/step_inputs.due``) knows which steps bring an
image, and the simulator, waiting for that reader, answers from that step's state.
``~reset`` (``std_srvs/Trigger``): as launched, for the next run of one launch (the simulator
rewound: the next ``/clock`` time above 0 is a step; the sensors' handles and clipping planes
asked again); see ``nodes/node_reset.py`` for what a reset promises.
"""
import io
import math
import struct
import time
from typing import Optional, Sequence

import numpy as np
import rospy
from sensor_msgs.msg import Image
from rospy.numpy_msg import numpy_msg
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Float32MultiArray, MultiArrayDimension
from std_srvs.srv import Trigger, TriggerResponse
from vrep_common.srv import (
    simRosGetObjectFloatParameter, simRosGetVisionSensorDepthBuffer,
    simRosGetVisionSensorDepthBufferResponse)

from epuck_vrep_compat.compat import thesis_names
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.topics import KINECT_DEPTH_IMAGE_TOPIC, NODE_RESET_SERVICE
from epuck_vrep_compat.ros.common.params import read_typed
from epuck_vrep_compat.thesis import params
from epuck_vrep_compat.thesis.cameras import IMAGE_SERVICES, read_image, stamp_header
from epuck_vrep_compat.thesis.vrep_client import VrepClient, run_node, spin_periodic

DEFAULT_NEAR_M = 0.5
DEFAULT_FAR_M = 5.0
STEP_EPS = 1e-6          # a step's time within this many periods of a multiple falls on it


class DepthBufferAsArray(simRosGetVisionSensorDepthBuffer):
    """simRosGetVisionSensorDepthBuffer whose response's ``buffer`` arrives as a numpy float32
    array (the same service on the wire): 307 200 values are one copy, not 307 200 floats."""
    _response_class = numpy_msg(simRosGetVisionSensorDepthBufferResponse)


_Float32MultiArrayOfArray = numpy_msg(Float32MultiArray)


def depth_buffer_message(resolution: Sequence[int], buffer: Sequence[float]) -> Float32MultiArray:
    """A std_msgs/Float32MultiArray (its data a numpy array, written to the wire in one copy)."""
    width, height = resolution
    msg = _Float32MultiArrayOfArray(data=np.asarray(buffer, dtype=np.float32))
    msg.layout.dim = [MultiArrayDimension(label="height", size=height, stride=width * height),
                      MultiArrayDimension(label="width", size=width, stride=width)]
    return msg


class _DepthImage(Image):
    """A sensor_msgs/Image whose ``data`` is the depth array itself (float32 (H, W), C order),
    written to the wire from its own memory: the same bytes as ``data=depth.tobytes()``, less
    the two copies of a 1.2 MB image that a bytes field and its packing would cost."""

    def serialize(self, buff):
        pixels, self.data = self.data, b""
        try:
            fields = io.BytesIO()
            super().serialize(fields)       # every field, ``data`` (the last) empty
        finally:
            self.data = pixels
        buff.write(fields.getbuffer()[:-4])
        buff.write(_COUNT.pack(pixels.nbytes))
        buff.write(memoryview(pixels).cast("B"))


_COUNT = struct.Struct("<I")


def depth_image(resolution: Sequence[int], buffer: Sequence[float], near_m: float,
                far_m: float) -> Optional[Image]:
    """32FC1 depth [m], top row first; None when the buffer does not match the resolution.
    Its ``data`` is a float32 array (H, W) (bytes-like: ``np.frombuffer`` reads it)."""
    if len(resolution) != 2:
        return None
    width, height = resolution
    if width <= 0 or height <= 0 or len(buffer) != width * height:
        return None
    value = np.asarray(buffer, dtype=np.float32).reshape(height, width)[::-1]
    # near + (far - near) * value in float32, as numpy computes it with Python floats, but
    # into one array: the image's own
    depth = np.multiply(value, np.float32(far_m - near_m), dtype="<f4")
    depth += np.float32(near_m)
    np.copyto(depth, np.inf, where=value >= 1.0)
    return _DepthImage(height=height, width=width, encoding="32FC1", is_bigendian=0,
                       step=4 * width, data=depth)


class Kinect:
    """The Kinect node: depth buffer, depth image and colour image from /vrep."""

    def __init__(self):
        self.depth_sensor = params.read_name("depth_sensor", thesis_names.KINECT_DEPTH_SENSOR)
        self.rgb_sensor = params.read_name("rgb_sensor", thesis_names.KINECT_RGB_SENSOR)
        self.near_m = params.read_float("near_clipping_m", DEFAULT_NEAR_M)
        self.far_m = params.read_float("far_clipping_m", DEFAULT_FAR_M, minimum=self.near_m)
        self.rate_hz = params.read_rate_hz()
        self.clock, self._last_step, self._ready = None, rospy.Time(0), False
        if read_typed("lockstep", False, bool):     # hears every step before it publishes
            self.clock = rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=100)
            while not rospy.is_shutdown() and self.clock.get_num_connections() == 0:
                time.sleep(0.02)
        self.client = VrepClient(dict(
            IMAGE_SERVICES, simRosGetVisionSensorDepthBuffer=DepthBufferAsArray,
            simRosGetObjectFloatParameter=simRosGetObjectFloatParameter))
        # images and buffers: only the newest is worth sending
        self._buffer_pub = rospy.Publisher(thesis_names.KINECT_DEPTH_BUFFER_TOPIC,
                                           Float32MultiArray, queue_size=1)
        self._depth_pub = rospy.Publisher(KINECT_DEPTH_IMAGE_TOPIC, Image, queue_size=1)
        self._rgb_pub = rospy.Publisher(thesis_names.KINECT_RGB_IMAGE_TOPIC, Image, queue_size=1)
        self._clipping_checked = False
        self._ready = True
        self._reset = rospy.Service("~" + NODE_RESET_SERVICE, Trigger, self._on_reset)
        rospy.loginfo("%s: depth '%s' -> %s, %s (clipping %.2f .. %.2f m); rgb '%s' -> %s; "
                      "rate %.1f Hz", rospy.get_name(), self.depth_sensor,
                      thesis_names.KINECT_DEPTH_BUFFER_TOPIC, KINECT_DEPTH_IMAGE_TOPIC,
                      self.near_m, self.far_m, self.rgb_sensor, thesis_names.KINECT_RGB_IMAGE_TOPIC,
                      self.rate_hz)

    def _check_clipping(self, handle: int):
        planes = [self.client.call("simRosGetObjectFloatParameter", handle=handle,
                                   parameterID=p)
                  for p in (vc.VISIONFLOATPARAM_NEAR_CLIPPING, vc.VISIONFLOATPARAM_FAR_CLIPPING)]
        if any(res is None or res.result == -1 for res in planes):
            return                          # the simulator cannot say: trust the parameters
        self._clipping_checked = True
        near_m, far_m = (res.parameterValue for res in planes)
        if not (math.isclose(near_m, self.near_m, rel_tol=1e-4)
                and math.isclose(far_m, self.far_m, rel_tol=1e-4)):
            rospy.logwarn("%s: sensor '%s' clips at %.3f .. %.3f m but ~near_clipping_m, "
                          "~far_clipping_m say %.3f .. %.3f m: depths in metres will be wrong",
                          rospy.get_name(), self.depth_sensor, near_m, far_m, self.near_m,
                          self.far_m)

    def _publish_depth(self, handle: int, stamp=None):
        if not self._clipping_checked:
            self._check_clipping(handle)
        res = self.client.call("simRosGetVisionSensorDepthBuffer", handle=handle)
        if res is None:
            return
        image = depth_image(res.resolution, res.buffer, self.near_m, self.far_m)
        if res.result == -1 or image is None:
            self.client.log.warn("depth", "%s: simRosGetVisionSensorDepthBuffer failed for "
                                 "'%s' (result %d, resolution %s, %d values)", rospy.get_name(),
                                 self.depth_sensor, res.result, list(res.resolution),
                                 len(res.buffer))
            self.client.forget_handle(self.depth_sensor)
            return
        if stamp is not None:
            image.header.stamp = stamp
        stamp_header(image.header, self.depth_sensor)
        self._buffer_pub.publish(depth_buffer_message(res.resolution, res.buffer))
        self._depth_pub.publish(image)

    def step(self, stamp=None):
        """One reading of each sensor somebody subscribes to (``stamp``: the images' stamp;
        None: the time now)."""
        depth = self.client.handle(self.depth_sensor, "vision sensor")      # warn while missing
        rgb = self.client.handle(self.rgb_sensor, "vision sensor")
        if depth >= 0 and (self._buffer_pub.get_num_connections()
                           or self._depth_pub.get_num_connections()):
            self._publish_depth(depth, stamp)
        if rgb >= 0 and self._rgb_pub.get_num_connections():
            image = read_image(self.client, rgb, self.rgb_sensor)
            if image is not None:
                if stamp is not None:
                    image.header.stamp = stamp
                self._rgb_pub.publish(image)

    def _on_reset(self, _req):
        """``~reset``: as launched (see the module)."""
        self._last_step = rospy.Time(0)
        self._clipping_checked = False
        for name in (self.depth_sensor, self.rgb_sensor):
            self.client.forget_handle(name)
        rospy.loginfo("%s: reset: as launched", rospy.get_name())
        return TriggerResponse(success=True, message="")

    def _on_clock(self, msg):
        """Lock-step: a new step reads when its time passes a multiple of the period."""
        if msg.clock <= self._last_step:
            return
        previous, self._last_step = self._last_step.to_sec(), msg.clock
        if self._ready and (math.floor(msg.clock.to_sec() * self.rate_hz + STEP_EPS)
                            > math.floor(previous * self.rate_hz + STEP_EPS)):
            self.step(msg.clock)

    def run(self):
        if self.clock is not None:
            rospy.spin()
        else:
            spin_periodic(self.rate_hz, self.step)


def main() -> int:
    return run_node(thesis_names.KINECT_NODE, Kinect)

"""Each robot's camera: rendered by the core's ray-cast camera, only while someone subscribes.

Unlike the V-REP script (frame id ``"a"``, bottom row first, ``is_bigendian`` 1) the image is
top row first, frame ``<robot>/camera_optical``, with a latched ``camera_info`` beside it.
Images go out with the step's other messages through the step batch (the core's writer, off the
interpreter): a slow viewer gets a backlog, then loses whole batches, instead of stalling the step.
A step looks only at the cameras someone subscribes to (recounted on subscribe events), so a
thousand unwatched cameras cost nothing per step.
:meth:`CameraFace.sync` follows robots added to and removed from the simulation.
"""
import numpy as np
import rospy
from sensor_msgs.msg import CameraInfo, Image

from epuck_vrep_compat.compat import epuck_names
from epuck_vrep_compat.epuck.cameras import render_robot_cameras
from epuck_vrep_compat.policy.observation import gray_levels
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.messages import camera_info
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher
from epuck_vrep_compat.ros.transport.wire import ImageWire


class _Watch(rospy.SubscribeListener):
    """Marks the face's list of watched cameras stale on every (un)subscription."""

    def __init__(self, face):
        super().__init__()
        self._face = face

    def peer_subscribe(self, topic_name, topic_publish, peer_publish):
        self._face.watched_stale = True

    def peer_unsubscribe(self, topic_name, num_peers):
        self._face.watched_stale = True


class CameraFace(Face):
    """Each robot's ``camera`` image (at the camera's rate, while someone subscribes) and its
    latched ``camera_info``."""

    def __init__(self, profile, sim, mode="rgb"):
        """``mode``: "rgb" (rgb8) or "gray" (mono8, ITU-R BT.601 luma, the drivers' grey)."""
        self.profile = profile
        self.mode = mode
        self.sim = sim
        self._period_s = 1.0 / sim.epucks.camera.rate_hz
        self._cameras = {}            # robot name -> _Camera
        self._watch = _Watch(self)
        self._watched = []            # the cameras with a subscriber, as of the last recount
        self.watched_stale = True
        self.sync()

    def sync(self):
        """Follow the simulation's robots (between steps): a camera for each new robot, none
        for each removed one."""
        names_now = self.sim.epucks.robot_names
        for name in [n for n in self._cameras if n not in names_now]:
            self._cameras.pop(name).close()
        for name in names_now:
            if name not in self._cameras:
                self._cameras[name] = _Camera(self.profile, self.sim.epucks.camera, name,
                                              self._watch, gray=self.mode == "gray")
        self.watched_stale = True

    def publish(self, step: Step):
        """Render and publish each camera that is due and has a subscriber."""
        if self.watched_stale:
            self.watched_stale = False      # first: an event during the recount marks it again
            self._watched = [c for c in self._cameras.values()
                             if c.image.impl is not None and c.image.impl.has_connections()]
        now = self.sim.time_s
        due = [c for c in self._watched
               if now + 1e-9 >= c.next_due_s and c.image.impl.has_connections()]
        if not due:
            return
        images = render_robot_cameras(self.sim.epucks, [c.robot for c in due])
        if self.mode == "gray":
            images = gray_levels(images).astype(np.uint8)     # the drivers' gray mode
        for camera, image in zip(due, images):
            camera.next_due_s = now + self._period_s
            step.batch.add_frame(camera.image, camera.frame(step.secs, step.nsecs, image))


class _Camera:
    """One robot's camera: its vision sensor, image topic and latched camera_info."""

    def __init__(self, profile, spec, name, watch, gray=False):
        self.robot = name
        frame_id = profile.frame(name, epuck_names.CAMERA_FRAME)
        self.next_due_s = 0.0
        self._wire = ImageWire(frame_id, spec.width, spec.height, "mono8" if gray else "rgb8")
        self.image = synchronous_publisher(profile.topic(name, "camera"), Image,
                                           subscriber_listener=watch)
        # published once, here: latched and without rospy's queue, whose writer thread per
        # connection would be a thousand idle threads at 1000 robots all subscribed
        self.info = synchronous_publisher(profile.topic(name, "camera_info"), CameraInfo,
                                          latch=True)
        self.info.publish(camera_info(spec.width, spec.height, spec.vertical_fov_rad,
                                      frame_id))

    def frame(self, secs: int, nsecs: int, image: np.ndarray) -> bytes:
        """The image (rgb8 or mono8 pixels, top row first) as a TCPROS frame, laid out once
        (``wire.ImageWire``)."""
        return self._wire.frame(secs, nsecs, np.ascontiguousarray(image, dtype=np.uint8).data)

    def close(self):
        self.image.unregister()
        self.info.unregister()

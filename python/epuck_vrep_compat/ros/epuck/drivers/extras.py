"""The driver topics beyond the shared ones (profile ``extras``): the e-puck2's ``imu`` (with
roll and pitch from the accelerometer), ``dist_sens``, ``mag_field``, ``mag_field_vector``,
``battery``, ``floor``, ``microphone``; the e-puck 1 driver's ``floor``, ``microphone`` and
``motor_speed`` markers.

Readings come from the model after each step (:class:`~epuck_vrep_compat.epuck.epuck2_sensors.
Epuck2Sensors` and the swarm). As the other per-step topics, the fixed-size messages are laid
out once (``extras_wire``) and each step writes only their numbers, for all robots at once;
the text markers are re-serialised only when their text changes. Nothing is built while nobody
subscribes (a subscribe listener counts the connections).
"""
import numpy as np
import rospy
from sensor_msgs.msg import BatteryState, Imu, MagneticField, Range
from visualization_msgs.msg import Marker

from epuck_vrep_compat.compat import epuck_names
from epuck_vrep_compat.ros.epuck.drivers import extras_messages as build
from epuck_vrep_compat.ros.epuck.drivers.extras_wire import TextMarkerCache, sentinel_batch
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher

GRAVITY_SIGN = {"ros": 1.0, "vrep": -1.0}
# profile extra -> its topics; every topic's message class
_ROLE_TOPICS = {"imu": ("imu",), "dist_sens": ("dist_sens",),
                "mag_field": ("mag_field", "mag_field_vector"), "battery": ("battery",),
                "floor": ("floor",), "microphone": ("microphone",),
                "motor_speed": ("motor_speed",)}
_CLASSES = {"imu": Imu, "dist_sens": Range, "mag_field": MagneticField,
            "mag_field_vector": Marker, "battery": BatteryState, "floor": Marker,
            "microphone": Marker, "motor_speed": Marker}
_TEXT_TOPICS = ("floor", "microphone", "motor_speed")
E_PUCK1_FLOOR_VALUES = 5            # the e-puck 1 driver prints five ground-module values


def _set(path):
    """A setter writing values into the named fields of a message (dotted paths)."""
    def setter(msg, values):
        for p, v in zip(path, values):
            obj = msg
            *parents, last = p.split(".")
            for attr in parents:
                obj = obj[int(attr)] if attr.isdigit() else getattr(obj, attr)
            setattr(obj, last, v)
    return setter


_XYZ = ("x", "y", "z")
_FIELDS = {
    "imu": {"accel": (_set([f"linear_acceleration.{a}" for a in _XYZ]), "<f8", 3),
            "gyro": (_set([f"angular_velocity.{a}" for a in _XYZ]), "<f8", 3),
            "quat": (_set([f"orientation.{a}" for a in "xyzw"]), "<f8", 4)},
    "dist_sens": {"range": (_set(["range"]), "<f4", 1)},
    "mag_field": {"field": (_set([f"magnetic_field.{a}" for a in _XYZ]), "<f8", 3)},
    "mag_field_vector": {"end": (_set(["points.1.x", "points.1.y"]), "<f8", 2)},
    "battery": {"voltage": (_set(["voltage"]), "<f4", 1),
                "percentage": (_set(["percentage"]), "<f4", 1)}}


class _Listening(rospy.SubscribeListener):
    """Keeps ``face.listening`` = subscriber connections of all the face's publishers."""

    def __init__(self, face):
        super().__init__()
        self._face = face

    def recount(self):
        self._face.listening = sum(len(p.impl.connections) for pubs in
                                   list(self._face.robots.values()) for p in pubs.values()
                                   if p.impl is not None)

    def peer_subscribe(self, topic_name, topic_publish, peer_publish):
        self.recount()

    def peer_unsubscribe(self, topic_name, num_peers):
        self.recount()


class ExtrasFace(Face):
    """Each robot's extra driver topics, as its profile lists them."""

    def __init__(self, profile, sim, sensors, accel_sign="ros"):
        """``sensors``: the simulation's Epuck2Sensors extension."""
        self.profile = profile
        self.sim = sim
        self.sensors = sensors
        self.gravity_sign = GRAVITY_SIGN[accel_sign]
        self.topics = [t for role in profile.extras for t in _ROLE_TOPICS.get(role, ())]
        self.robots = {}                # robot name -> {topic: publisher}, in row order
        self.listening = 0
        self._listener = _Listening(self)
        self._texts = TextMarkerCache()
        self.sync()

    def sync(self):
        names_now = list(self.sim.epucks.robot_names)
        for name in [n for n in self.robots if n not in names_now]:
            for pub in self.robots.pop(name).values():
                pub.unregister()
            self._texts.forget(name)
        self.robots = {name: self.robots.get(name) or {t: synchronous_publisher(
            self.profile.topic(name, t), _CLASSES[t], subscriber_listener=self._listener)
            for t in self.topics} for name in names_now}
        self._batches = {t: self._lay_out(t, names_now) for t in self.topics if t in _FIELDS}
        self._listener.recount()

    def _lay_out(self, topic, robots):
        frame = self.profile.frame
        zero = (0.0, 0.0, 1.0)
        templates = {
            "imu": lambda r: build.imu(None, frame(r, epuck_names.BASE_FRAME), zero, zero),
            "dist_sens": lambda r: build.dist_sens(None, frame(r, epuck_names.DIST_SENS_FRAME),
                                                   1.0),
            "mag_field": lambda r: build.mag_field(None, frame(r, epuck_names.BASE_FRAME), zero),
            "mag_field_vector": lambda r: build.mag_field_vector(
                None, frame(r, epuck_names.BASE_FRAME), (1.0, 0.0, 0.0)),
            "battery": lambda r: build.battery(None, frame(r, epuck_names.BASE_FRAME), 4.2)}
        if not robots:
            return None
        return sentinel_batch([templates[topic](r) for r in robots], _FIELDS[topic])

    def publish(self, step: Step):
        if not self.listening:
            return
        packed = {}
        secs, nsecs, batch = step.secs, step.nsecs, step.batch
        for i, (name, pubs) in enumerate(self.robots.items()):
            for topic, pub in pubs.items():
                if not pub.impl.connections:
                    continue
                if topic in _TEXT_TOPICS:
                    batch.add_frame(pub, self._text_frame(topic, i, name, secs, nsecs))
                    continue
                data = packed.get(topic)
                if data is None:
                    data = packed[topic] = self._pack(topic, secs, nsecs)
                start, end = self._batches[topic].bounds(i)
                batch.add_frame(pub, data[start:end])

    def _pack(self, topic, secs, nsecs) -> bytes:
        s, swarm = self.sensors, self.sim.epucks.swarm
        pack = self._batches[topic].pack
        if topic == "imu":
            accel = swarm.accel * self.gravity_sign
            return pack(secs, nsecs, accel=accel, gyro=swarm.gyro, quat=build.tilt_quat(accel))
        if topic == "dist_sens":
            return pack(secs, nsecs, range=np.clip(s.tof_m, build.DIST_SENS_MIN_M,
                                                   build.DIST_SENS_MAX_M))
        if topic == "mag_field":
            return pack(secs, nsecs, field=s.mag_tesla)
        if topic == "mag_field_vector":
            horizontal = s.mag_tesla[:, :2]
            norm = np.hypot(horizontal[:, 0], horizontal[:, 1])[:, None]
            return pack(secs, nsecs, end=horizontal / np.where(norm > 0.0, norm, 1.0))
        percentage = ((s.battery_v - build.BATTERY_MIN_V)
                      / (build.BATTERY_MAX_V - build.BATTERY_MIN_V))
        return pack(secs, nsecs, voltage=s.battery_v, percentage=percentage)

    def _text_frame(self, topic, i, name, secs, nsecs) -> bytes:
        frame = self.profile.frame(name, epuck_names.BASE_FRAME)
        if topic == "floor":
            values, make = self._floor_values(i), build.floor
        elif topic == "microphone":
            values, make = self.sensors.mic[i][:self.profile.microphones], build.microphone
        else:
            values, make = self._motor_steps(i), build.motor_speed
        values = [int(v) for v in values]
        return self._texts.frame((name, topic), str(values),
                                 lambda: make(None, frame, values), secs, nsecs)

    def _floor_values(self, i):
        values = list(self.sensors.floor[i])
        if self.profile.name == "epuck_driver":
            values += [0] * (E_PUCK1_FLOOR_VALUES - len(values))
        return values

    def _motor_steps(self, i):
        """The motors' speeds in steps/s (1000 per revolution), as the e-puck 1 reports them."""
        wheels = self.sim.epucks.command.wheel_rad_s[i]
        return [int(w * 1000.0 / (2.0 * np.pi)) for w in wheels]

"""The driver topics beyond the shared ones (profile ``extras``): the e-puck2's ``imu`` (with
roll and pitch from the accelerometer), ``dist_sens``, ``mag_field``, ``mag_field_vector``,
``battery``, ``floor``, ``microphone``; the e-puck 1 driver's ``floor``, ``microphone`` and
``motor_speed`` markers.

Readings come from the model after each step (:class:`~epuck_vrep_compat.sim.epuck2_sensors.
Epuck2Sensors` and the swarm); a message is built only for a topic someone subscribes to, so a
swarm nobody listens to costs one check per topic and step.
"""
import numpy as np
import rospy
from sensor_msgs.msg import BatteryState, Imu, MagneticField, Range
from visualization_msgs.msg import Marker

from epuck_vrep_compat.ros.epuck import extras_messages as build
from epuck_vrep_compat.ros.epuck import names
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher

GRAVITY_SIGN = {"ros": 1.0, "vrep": -1.0}
# role -> (topics of the role, message class); mag_field also feeds mag_field_vector
_TOPICS = {"imu": (("imu",), Imu), "dist_sens": (("dist_sens",), Range),
           "mag_field": (("mag_field", "mag_field_vector"), None), "battery": (("battery",),
                                                                      BatteryState),
           "floor": (("floor",), Marker), "microphone": (("microphone",), Marker),
           "motor_speed": (("motor_speed",), Marker)}
_CLASSES = {"mag_field": MagneticField, "mag_field_vector": Marker}
E_PUCK1_FLOOR_VALUES = 5            # the e-puck 1 driver prints five ground-module values


class _Listening(rospy.SubscribeListener):
    """Keeps ``face.listening`` = subscriber connections of all the face's publishers, so a
    step nobody listens to costs one test."""

    def __init__(self, face):
        super().__init__()
        self._face = face

    def _recount(self):
        self._face.listening = sum(len(p.impl.connections) for pubs in
                                   list(self._face._robots.values()) for p in pubs.values()
                                   if p.impl is not None)

    def peer_subscribe(self, topic_name, topic_publish, peer_publish):
        self._recount()

    def peer_unsubscribe(self, topic_name, num_peers):
        self._recount()


class ExtrasFace(Face):
    """Each robot's extra driver topics, as its profile lists them."""

    def __init__(self, profile, sim, sensors, accel_sign="ros"):
        """``sensors``: the simulation's Epuck2Sensors extension (None: no e-puck2 sensors,
        then only motor_speed, floor and microphone of the e-puck 1 are available)."""
        self.profile = profile
        self.sim = sim
        self.sensors = sensors
        self.gravity_sign = GRAVITY_SIGN[accel_sign]
        self.topics = [t for role in profile.extras if role in _TOPICS
                       for t in _TOPICS[role][0]]
        self._robots = {}               # robot name -> {topic: publisher}
        self.listening = 0
        self._listener = _Listening(self)
        self.sync()

    def sync(self):
        names_now = self.sim.robot_names
        for name in [n for n in self._robots if n not in names_now]:
            for pub in self._robots.pop(name).values():
                pub.unregister()
        for name in names_now:
            if name not in self._robots:
                self._robots[name] = {t: synchronous_publisher(
                    self.profile.topic(name, t), self._class(t),
                    subscriber_listener=self._listener) for t in self.topics}
        self._listener._recount()

    @staticmethod
    def _class(topic):
        for role, (topics, cls) in _TOPICS.items():
            if topic in topics:
                return cls or _CLASSES[topic]
        raise KeyError(topic)

    def publish(self, step: Step):
        if not self.listening:
            return
        stamp = None
        batch = step.batch
        for i, name in enumerate(self.sim.robot_names):
            pubs = self._robots.get(name)
            if pubs is None:
                continue
            for topic, pub in pubs.items():
                if not pub.impl.connections:
                    continue
                if stamp is None:
                    stamp = step.stamp
                batch.add(pub, self._message(topic, i, name, stamp))

    def _message(self, topic, i, name, stamp):
        frame = self.profile.frame(name, names.BASE_FRAME)
        s, swarm = self.sensors, self.sim.swarm
        if topic == "imu":
            return build.imu(stamp, frame, swarm.accel[i] * self.gravity_sign, swarm.gyro[i])
        if topic == "dist_sens":
            return build.dist_sens(stamp, self.profile.frame(name, names.DIST_SENS_FRAME),
                                   s.tof_m[i])
        if topic == "mag_field":
            return build.mag_field(stamp, frame, s.mag_tesla[i])
        if topic == "mag_field_vector":
            return build.mag_field_vector(stamp, frame, s.mag_tesla[i])
        if topic == "battery":
            return build.battery(stamp, frame, s.battery_v[i])
        if topic == "floor":
            return build.floor(stamp, frame, self._floor_values(i))
        if topic == "microphone":
            return build.microphone(stamp, frame, s.mic[i][:self.profile.microphones])
        return build.motor_speed(stamp, frame, self._motor_steps(i))

    def _floor_values(self, i):
        values = list(self.sensors.floor[i])
        if self.profile.name == "epuck_driver":
            values += [0] * (E_PUCK1_FLOOR_VALUES - len(values))
        return values

    def _motor_steps(self, i):
        """The motors' speeds in steps/s (1000 per revolution), as the e-puck 1 reports them."""
        wheels = self.sim.command.wheel_rad_s[i]
        return [int(w * 1000.0 / (2.0 * np.pi)) for w in wheels]

"""LEDs (``cmd_led`` in, latched ``led_state`` out) and the rviz markers of the scene.

``led_state`` goes through the step batch like every per-step topic, latched by it
(``ros/transport/latched.py``): a late subscriber gets the last state at the next flush, and a
subscriber to every robot's costs the node no writer thread per connection.

The markers are latched and ``frame_locked`` to each robot's base_link, so rviz moves them with
TF and they are re-sent only when an LED changes or the scene's objects change; every array
starts with a DELETEALL, so a removed robot or obstacle leaves rviz too. The LED states are the
model's (:class:`epuck_vrep_compat.epuck.leds.RobotLeds`, by robot name): ``cmd_led`` sets them
there, as ``cmd_vel`` sets wheel speeds, and this face reads them after each step.
"""
import threading

import rospy
from std_msgs.msg import ColorRGBA, UInt8MultiArray
from visualization_msgs.msg import Marker, MarkerArray

from epuck_vrep_compat.compat import epuck_names
from epuck_vrep_compat.compat.frames import ODOM_FRAME
from epuck_vrep_compat.compat.topics import NODE_NAMESPACE
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.epuck import commands
from epuck_vrep_compat.ros.epuck.drivers import epuck2_leds
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.messages import shape_marker
from epuck_vrep_compat.scene.epuck_model import led_positions

MARKER_TOPIC = NODE_NAMESPACE + "markers"
_LED_ON = ColorRGBA(1.0, 0.05, 0.05, 1.0)
_LED_OFF = ColorRGBA(0.25, 0.1, 0.1, 1.0)


class LedFace(Face):
    """Each robot's ``cmd_led`` and latched ``led_state``, and the scene's rviz markers."""

    def __init__(self, profile, sim, batch):
        """``batch``: the node's ``StepBatch``, which sends and latches ``led_state``."""
        self.profile = profile
        self.sim = sim
        self.batch = batch
        self._lock = threading.Lock()
        self._robots = {}             # robot name -> _Leds
        self._seen_changes = -1       # the LED model's change count at the last publication
        self._log = ThrottledLog()
        self._colours = {}            # robot name -> {LED index: (r, g, b)} (e-puck2 RGB LEDs)
        self._markers = rospy.Publisher(MARKER_TOPIC, MarkerArray, queue_size=1, latch=True)
        self.sync()

    def sync(self):
        """Follow the simulation's robots and objects (between steps): LED topics for new
        robots (all LEDs off), none for removed ones; the markers are re-sent."""
        names = self.sim.epucks.robot_names
        with self._lock:
            gone = [leds for name, leds in self._robots.items() if name not in names]
            self._robots = {name: self._robots.get(name) or _Leds(self, name) for name in names}
            self._markers_dirty = True
        for leds in gone:
            leds.close()

    def _on_cmd_led(self, msg, name):
        """A robot's ``cmd_led`` (rospy thread): the new states into the model, whole (a toggle
        reads the states it changes)."""
        data = bytearray(msg.data)
        result = self.sim.epucks.leds.update(
            name, lambda current: commands.apply_led_command(self.profile.name, current, data))
        if isinstance(result, str):
            self._log.warn(f"{name}:cmd_led", "%s: %s; ignored", name, result)

    def _on_rgb_leds(self, msg, name):
        """The e-puck2's ``rgb_leds`` (rospy thread): states and colours of its RGB LEDs (the
        colours, for the markers, before the states that make them re-sent)."""
        data = bytearray(msg.data)

        def change(current):
            result = epuck2_leds.apply_rgb_command(current, data)
            if isinstance(result, str):
                return result
            self._colours.setdefault(name, {}).update(result[1])
            return result[0]
        result = self.sim.epucks.leds.update(name, change)
        if isinstance(result, str):
            self._log.warn(f"{name}:rgb_leds", "%s: %s; ignored", name, result)

    def publish(self, step: Step):
        """After a step: re-send the LED states set since, and the markers with them."""
        model = self.sim.epucks.leds
        changes = model.changes
        with self._lock:
            if changes == self._seen_changes and not self._markers_dirty:
                return
            self._seen_changes, self._markers_dirty = changes, False
            robots = list(self._robots.items())
        state = {}
        for name, leds in robots:
            entry = model.get(name)
            if entry is None:
                continue                                # removed; sync() follows
            state[name], stamp = entry
            if stamp != leds.sent:
                leds.sent = stamp
                step.batch.add_latched(leds.publisher,
                                       UInt8MultiArray(data=bytes(state[name])))
        self._markers.publish(self._marker_array(state))

    def publish_idle(self, step: Step):
        """While not stepping too: LED commands still change the latched states."""
        self.publish(step)

    def _marker_array(self, state):
        """``state``: robot name -> its 10 LED values."""
        out = MarkerArray()
        clear = Marker()
        clear.action = Marker.DELETEALL
        out.markers.append(clear)
        out.markers.extend(self._arena_markers())
        model = self.sim.epucks.model
        leds = led_positions()
        for name, values in state.items():
            frame = self.profile.frame(name, epuck_names.BASE_FRAME)
            body = shape_marker(frame, name, 0, Marker.CYLINDER,
                                (0, 0, 0.5 * model.body_height_m),
                                (2 * model.body_radius_m, 2 * model.body_radius_m,
                                 model.body_height_m), ColorRGBA(0.9, 0.9, 0.85, 0.9))
            out.markers.append(body)
            for k, (x, y, z) in enumerate(leds[:9]):
                rgb = self._colours.get(name, {}).get(k)
                color = (_LED_OFF if not values[k] else _LED_ON if rgb is None
                         else ColorRGBA(rgb[0], rgb[1], rgb[2], 1.0))
                out.markers.append(shape_marker(frame, name + "/leds", k, Marker.SPHERE,
                                                (x, y, z), (0.006, 0.006, 0.006), color))
        return out

    def _arena_markers(self):
        markers = []
        for obj in self.sim.registry.objects():
            if obj.robot is not None or "size" not in obj.properties:
                continue
            shape = Marker.CUBE if obj.properties["shape"] == "box" else Marker.CYLINDER
            r, g, b = obj.properties["color"]
            markers.append(shape_marker(ODOM_FRAME, "arena", obj.handle, shape,
                                        obj.local_position, obj.properties["size"],
                                        ColorRGBA(r, g, b, 1.0), obj.local_quat))
        return markers


class _Leds:
    """One robot's latched ``led_state`` and its ``cmd_led``; ``sent``: the model's change
    stamp of the states last published (None: nothing published yet)."""

    def __init__(self, face, name):
        profile = face.profile
        self.sent = None
        self.publisher = face.batch.latched_publisher(profile.topic(name, "led_state"),
                                                      UInt8MultiArray)
        self._subscriber = rospy.Subscriber(profile.topic(name, "cmd_led"), UInt8MultiArray,
                                            face._on_cmd_led, name, queue_size=10)
        self._rgb = (rospy.Subscriber(profile.topic(name, "rgb_leds"), UInt8MultiArray,
                                      face._on_rgb_leds, name, queue_size=10)
                     if "rgb_leds" in profile.extras else None)

    def close(self):
        self._subscriber.unregister()
        if self._rgb is not None:
            self._rgb.unregister()
        self.publisher.unregister()


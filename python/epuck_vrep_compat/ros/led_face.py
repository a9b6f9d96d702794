"""LEDs (``cmd_led`` in, latched ``led_state`` out) and the rviz markers of the scene.

The markers are latched and ``frame_locked`` to each robot's base_link, so rviz moves them with
TF and they are re-sent only when an LED changes.
"""
import threading

import numpy as np
import rospy
from std_msgs.msg import ColorRGBA, UInt8MultiArray
from visualization_msgs.msg import Marker, MarkerArray

from epuck_vrep_compat.ros import commands, names
from epuck_vrep_compat.scene.epuck_model import led_positions

MARKER_TOPIC = "/vrep/markers"
_LED_ON = ColorRGBA(1.0, 0.05, 0.05, 1.0)
_LED_OFF = ColorRGBA(0.25, 0.1, 0.1, 1.0)


class LedFace:
    def __init__(self, profile, sim):
        self.profile = profile
        self.sim = sim
        n = sim.size
        self.state = np.zeros((n, commands.LED_COUNT), dtype=np.uint8)
        self._lock = threading.Lock()
        self._dirty = set(range(n))
        self._markers_dirty = True
        self._led_pubs = [rospy.Publisher(profile.topic(name, "led_state"), UInt8MultiArray,
                                          queue_size=1, latch=True)
                          for name in sim.robot_names]
        self._subs = [rospy.Subscriber(profile.topic(name, "cmd_led"), UInt8MultiArray,
                                       self._on_cmd_led, i, queue_size=10)
                      for i, name in enumerate(sim.robot_names)]
        self._markers = rospy.Publisher(MARKER_TOPIC, MarkerArray, queue_size=1, latch=True)

    def _on_cmd_led(self, msg, index):
        with self._lock:
            result = commands.apply_led_command(self.profile.name, self.state[index],
                                                bytearray(msg.data))
            if isinstance(result, str):
                rospy.logwarn_throttle(5.0, f"{self.sim.robot_names[index]}: {result}; ignored")
                return
            self.state[index] = result
            self._dirty.add(index)
            self._markers_dirty = True

    def publish(self):
        """Called from the simulation thread after a step: re-send what changed."""
        with self._lock:
            dirty, self._dirty = self._dirty, set()
            markers_dirty, self._markers_dirty = self._markers_dirty, False
            state = self.state.copy()
        for i in sorted(dirty):
            self._led_pubs[i].publish(UInt8MultiArray(data=bytes(state[i])))
        if markers_dirty:
            self._markers.publish(self._marker_array(state))

    def _marker_array(self, state):
        out = MarkerArray()
        out.markers.extend(self._arena_markers())
        model = self.sim.model
        leds = led_positions()
        for i, name in enumerate(self.sim.robot_names):
            frame = self.profile.frame(name, names.BASE_FRAME)
            body = _marker(frame, name, 0, Marker.CYLINDER,
                           (0, 0, 0.5 * model.body_height_m),
                           (2 * model.body_radius_m, 2 * model.body_radius_m,
                            model.body_height_m), ColorRGBA(0.9, 0.9, 0.85, 0.9))
            out.markers.append(body)
            for k, (x, y, z) in enumerate(leds[:9]):
                color = _LED_ON if state[i][k] else _LED_OFF
                out.markers.append(_marker(frame, name + "/leds", k, Marker.SPHERE, (x, y, z),
                                           (0.006, 0.006, 0.006), color))
        return out

    def _arena_markers(self):
        markers = []
        for k, obj in enumerate(self.sim.registry.objects()):
            if obj.robot is not None or "size" not in obj.properties:
                continue
            shape = Marker.CUBE if obj.properties["shape"] == "box" else Marker.CYLINDER
            r, g, b = obj.properties["color"]
            markers.append(_marker(names.ODOM_FRAME, "arena", k, shape, obj.local_position,
                                   obj.properties["size"], ColorRGBA(r, g, b, 1.0),
                                   obj.local_quat))
        return markers


def _marker(frame, ns, marker_id, shape, position, scale, color, quat=(0, 0, 0, 1)):
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

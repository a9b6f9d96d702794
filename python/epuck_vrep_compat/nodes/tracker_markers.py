"""rviz markers of the operator tracker: the estimate (a cylinder of the operator's size), its
velocity (an arrow) and its 2-sigma position ellipse (a flat cylinder)."""
import math

import numpy as np
from geometry_msgs.msg import Point
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker

COLOUR = ColorRGBA(0.2, 0.4, 1.0, 0.8)


def _marker(frame, stamp, kind, marker_id):
    m = Marker(type=kind, action=Marker.ADD, ns="operator_tracker", id=marker_id)
    m.header.frame_id, m.header.stamp = frame, stamp
    m.pose.orientation.w = 1.0
    m.color = COLOUR
    return m


def estimate_markers(frame, stamp, state, cov_xy):
    """[body, velocity arrow, 2-sigma ellipse] for the state (x, y, vx, vy)."""
    x, y, vx, vy = (float(v) for v in state)
    body = _marker(frame, stamp, Marker.CYLINDER, 0)
    body.pose.position = Point(x, y, 0.76)
    body.scale.x = body.scale.y = 0.4
    body.scale.z = 1.52
    arrow = _marker(frame, stamp, Marker.ARROW, 1)
    arrow.points = [Point(x, y, 1.6), Point(x + vx, y + vy, 1.6)]
    arrow.scale.x, arrow.scale.y, arrow.scale.z = 0.04, 0.08, 0.1
    values, vectors = np.linalg.eigh(np.asarray(cov_xy, dtype=float))
    ellipse = _marker(frame, stamp, Marker.CYLINDER, 2)
    ellipse.pose.position = Point(x, y, 0.01)
    yaw = math.atan2(vectors[1, 1], vectors[0, 1])
    ellipse.pose.orientation.z, ellipse.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    ellipse.scale.x = 4.0 * math.sqrt(max(values[1], 1e-8))     # 2 sigma each side
    ellipse.scale.y = 4.0 * math.sqrt(max(values[0], 1e-8))
    ellipse.scale.z = 0.01
    ellipse.color = ColorRGBA(COLOUR.r, COLOUR.g, COLOUR.b, 0.3)
    return [body, arrow, ellipse]

"""rviz markers of the speed-and-separation supervisor: per robot the separation as a line
from the operator to the nearest link, and S_p as a translucent shell about that link's
closest point, coloured by state (green: full speed, amber: slowed, red: protective stop)."""
from geometry_msgs.msg import Point
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker

FULL, SLOWED, STOPPED = (ColorRGBA(0.1, 0.8, 0.2, 1.0), ColorRGBA(1.0, 0.65, 0.0, 1.0),
                         ColorRGBA(0.9, 0.1, 0.1, 1.0))


def state_colour(scale: float) -> ColorRGBA:
    return FULL if scale >= 1.0 else STOPPED if scale <= 0.0 else SLOWED


def robot_markers(frame, stamp, robot, index, operator_point, link_point, s_p, scale):
    """The two markers of one robot (ids 2 index and 2 index + 1 in namespace ``ssm``)."""
    colour = state_colour(scale)
    line = Marker(type=Marker.LINE_LIST, action=Marker.ADD, ns="ssm/" + robot, id=2 * index)
    line.header.frame_id, line.header.stamp = frame, stamp
    line.pose.orientation.w = 1.0
    line.scale.x = 0.02
    line.color = colour
    line.points = [Point(*operator_point), Point(*link_point)]
    shell = Marker(type=Marker.SPHERE, action=Marker.ADD, ns="ssm/" + robot, id=2 * index + 1)
    shell.header.frame_id, shell.header.stamp = frame, stamp
    shell.pose.position = Point(*link_point)
    shell.pose.orientation.w = 1.0
    shell.scale.x = shell.scale.y = shell.scale.z = 2.0 * max(s_p, 1e-3)
    shell.color = ColorRGBA(colour.r, colour.g, colour.b, 0.15)
    return [line, shell]

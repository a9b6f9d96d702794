"""The cell for rviz: ``/<robot>/robot_description`` (the robot's URDF, links named as their TF
frames, so a RobotModel display draws each arm from TF alone); ``/vrep/cell_markers`` (latched,
frame-locked markers for the operator, the laser, the cameras and the Kinect); a static
``world -> odom`` identity, so the scene's static objects (``/vrep/markers``, in ``odom``) and
any e-puck join the cell's tree."""
import rospy
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from epuck_vrep_compat.compat.cell_names import ros_robot_name
from epuck_vrep_compat.compat.frames import ODOM_FRAME, WORLD_FRAME
from epuck_vrep_compat.compat.topics import NODE_NAMESPACE, ROBOT_DESCRIPTION_PARAM
from epuck_vrep_compat.ros.messages import shape_marker
from epuck_vrep_compat.ros.transport.static_tf import static_transform

CELL_MARKER_TOPIC = NODE_NAMESPACE + "cell_markers"
_DEVICE_COLOR = ColorRGBA(0.15, 0.15, 0.15, 1.0)


class CellRviz:
    """Robot descriptions, the static ``world -> odom`` and the cell's markers."""

    def __init__(self, sim, static_tf):
        self._sim = sim
        for arm in sim.cell.arms:
            rospy.set_param(_description_param(arm.spec.name), arm.description())
        static_tf.set("cell_odom", [static_transform(WORLD_FRAME, ODOM_FRAME, (0, 0, 0),
                                                     (0, 0, 0, 1))])
        self._markers = rospy.Publisher(CELL_MARKER_TOPIC, MarkerArray, queue_size=1,
                                        latch=True)
        self.publish_markers()

    @staticmethod
    def forget_robot(name):
        """A removed robot's description goes."""
        if rospy.has_param(_description_param(name)):
            rospy.delete_param(_description_param(name))

    @staticmethod
    def describe(arm):
        """A robot added while running (a model loaded): its description."""
        rospy.set_param(_description_param(arm.spec.name), arm.description())

    def publish_markers(self):
        self._markers.publish(self._marker_array())

    def _marker_array(self):
        cell, registry = self._sim.cell, self._sim.registry
        out = MarkerArray()
        if cell.operator is not None:
            o = cell.operator.spec
            r, g, b = o.color
            color = ColorRGBA(r, g, b, 1.0)
            frame = registry.get(cell.operator_handles[0]).name
            out.markers.append(shape_marker(
                frame, "operator", 0, Marker.CYLINDER, (0, 0, cell.operator.body_centre_z),
                (2 * o.body_radius_m, 2 * o.body_radius_m, o.body_height_m), color))
            out.markers.append(shape_marker(
                frame, "operator", 1, Marker.SPHERE, (0, 0, cell.operator.head_centre_z),
                (2 * o.head_radius_m,) * 3, color))
        devices = []
        if cell.laser is not None:        # the URG's body: 50 x 50 x 70 mm
            devices.append((cell.laser_handle, Marker.CYLINDER, (0.05, 0.05, 0.07)))
        devices += [(c.handle, Marker.CUBE, (0.08, 0.08, 0.08)) for c in cell.cameras]
        devices += [(v.handle, Marker.CUBE, (0.07, 0.07, 0.07))
                    for v in (cell.kinect_depth, cell.kinect_rgb) if v is not None]
        for handle, shape, size in devices:
            out.markers.append(shape_marker(registry.get(handle).name, "devices", handle, shape,
                                            (0, 0, 0), size, _DEVICE_COLOR))
        return out


def _description_param(robot_name):
    return ROBOT_DESCRIPTION_PARAM.format(robot=ros_robot_name(robot_name))

"""A controller of the eight IR ``Range`` topics that answers each sensor cycle once.

``IrCycle`` keeps the latest reading of each of a robot's eight proximity sensors; when all
eight carry the same stamp (one step of the simulator, one sensor cycle of the real robot) it
calls the controller with the eight ranges and publishes the ``(v, w)`` it returns on
``cmd_vel`` (m/s and rad/s: run the simulator with ``cmd_vel_scaling:=si``). So the node
answers every step exactly once, whatever the real-time factor, and under the experiment
runner's lock-step a run is the same run every time. A course's template: a student writes
the control function, ``run`` does the ROS part.
"""
import math
import threading

import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Range

from epuck_vrep_compat.compat.epuck_names import PROXIMITY_COUNT, VREP


class IrCycle:
    """The readings of one sensor cycle, and the command once all eight are in."""

    def __init__(self, control, publisher):
        self.control, self.publisher = control, publisher
        self.ranges = [math.inf] * PROXIMITY_COUNT
        self.max_range = [0.0] * PROXIMITY_COUNT
        self.stamps = [None] * PROXIMITY_COUNT
        self.last = None
        self.lock = threading.Lock()

    def on_range(self, msg, k):
        with self.lock:
            if math.isfinite(msg.range):
                self.ranges[k], self.max_range[k] = msg.range, msg.max_range
            self.stamps[k] = msg.header.stamp
            stamp = self.stamps[0]
            if stamp == self.last or any(s != stamp for s in self.stamps):
                return
            self.last = stamp
            cmd = Twist()
            cmd.linear.x, cmd.angular.z = self.control(list(self.ranges), list(self.max_range))
            self.publisher.publish(cmd)


def closeness(ranges, max_ranges):
    """Each sensor's ``1 - range / max_range`` in [0, 1] (0: nothing seen)."""
    return [max(0.0, 1.0 - r / m) if m > 0.0 and math.isfinite(r) else 0.0
            for r, m in zip(ranges, max_ranges)]


def run(node_name, make_control):
    """Starts the node ``node_name`` driving ``~robot`` (default ePuck0) with the controller
    ``make_control()`` returns (called once the node is up, so it may read its private
    parameters): ``control(ranges_m, max_ranges_m) -> (v_m_s, w_rad_s)``. Returns 0 when ROS
    shuts down."""
    rospy.init_node(node_name)
    control = make_control()
    robot = rospy.get_param("~robot", VREP.robot_name(0))
    pub = rospy.Publisher(VREP.topic(robot, "cmd_vel"), Twist, queue_size=1)
    cycle = IrCycle(control, pub)
    subs = [rospy.Subscriber(VREP.topic(robot, f"proximity{k}"), Range, cycle.on_range, k,
                             queue_size=8) for k in range(PROXIMITY_COUNT)]
    rospy.spin()
    del subs
    return 0

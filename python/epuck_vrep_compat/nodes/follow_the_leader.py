"""Follow the leader (the e-puck paper's case study 5.2) with tf2 and a proportional controller.

The follower asks tf2 where the leader's base_link is in its own base_link frame (the robots
need not see each other with their 4 cm IR sensors) and steers towards it, keeping a gap:
``v = k_linear * (distance - gap)``, ``w = k_angular * bearing``, both clamped. It is ordinary ROS
code: the same node drives two real e-pucks with the driver's frame and topic names.

Parameters: ``~leader_frame`` (ePuck0/base_link), ``~follower_frame`` (ePuck1/base_link),
``~cmd_vel`` (/ePuck1/cmd_vel), ``~gap_m`` (0.12), ``~k_linear`` (3.0), ``~k_angular`` (3.0),
``~max_linear_m_s`` (0.12), ``~max_angular_rad_s`` (2.5), ``~rate_hz`` (20).
"""
import math

import rospy
import tf2_ros
from geometry_msgs.msg import Twist

from epuck_vrep_compat.compat.epuck_names import BASE_FRAME, VREP


def control(x: float, y: float, gap_m: float, k_linear: float, k_angular: float,
            max_linear: float, max_angular: float):
    """(v, w) towards a target at (x, y) in the follower's frame."""
    distance = math.hypot(x, y)
    bearing = math.atan2(y, x)
    v = k_linear * (distance - gap_m) * max(0.0, math.cos(bearing))
    w = k_angular * bearing
    return (min(max(v, -max_linear), max_linear), min(max(w, -max_angular), max_angular))


def main():
    rospy.init_node("follow_the_leader")
    leader = rospy.get_param("~leader_frame", VREP.frame(VREP.robot_name(0), BASE_FRAME))
    follower = rospy.get_param("~follower_frame", VREP.frame(VREP.robot_name(1), BASE_FRAME))
    gains = dict(gap_m=float(rospy.get_param("~gap_m", 0.12)),
                 k_linear=float(rospy.get_param("~k_linear", 3.0)),
                 k_angular=float(rospy.get_param("~k_angular", 3.0)),
                 max_linear=float(rospy.get_param("~max_linear_m_s", 0.12)),
                 max_angular=float(rospy.get_param("~max_angular_rad_s", 2.5)))
    rate_hz = float(rospy.get_param("~rate_hz", 20.0))
    if rate_hz <= 0.0 or not math.isfinite(rate_hz):
        rospy.logfatal("parameter '~rate_hz' must be a positive number, got %s", rate_hz)
        return 2
    cmd_vel = rospy.get_param("~cmd_vel", VREP.topic(VREP.robot_name(1), "cmd_vel"))
    pub = rospy.Publisher(cmd_vel, Twist, queue_size=1)
    buffer = tf2_ros.Buffer()
    tf2_ros.TransformListener(buffer)
    rospy.loginfo("follow_the_leader: %s follows %s (%s)", follower, leader, gains)
    rate = rospy.Rate(rate_hz)
    while not rospy.is_shutdown():
        try:
            t = buffer.lookup_transform(follower, leader, rospy.Time(0), rospy.Duration(0.5))
            v, w = control(t.transform.translation.x, t.transform.translation.y, **gains)
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException) as e:
            rospy.logwarn_throttle(5.0, f"follow_the_leader: no transform yet ({e}); stopping")
            v, w = 0.0, 0.0
        cmd = Twist()
        cmd.linear.x, cmd.angular.z = v, w
        pub.publish(cmd)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    return 0

"""Braitenberg obstacle avoidance from the eight IR ``Range`` topics: a leader for the demo.

Each sensor's closeness ``1 - range / max_range`` pushes the wheels away from what it sees.
Parameters: ``~robot`` (ePuck0), ``~speed_m_s`` (0.06), ``~rate_hz`` (20).
"""
import math

import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Range

# Per sensor: weight of its closeness on the turn rate (+ = turn left). Front-right sensors
# (0, 1, 2) turn left, front-left (5, 6, 7) turn right, rear ones hardly matter.
TURN_WEIGHTS = (2.0, 1.5, 0.6, 0.1, -0.1, -0.6, -1.5, -2.0)
BRAKE_WEIGHTS = (0.6, 0.3, 0.0, 0.0, 0.0, 0.0, 0.3, 0.6)


def command(closeness, speed_m_s):
    turn = sum(w * c for w, c in zip(TURN_WEIGHTS, closeness))
    brake = sum(w * c for w, c in zip(BRAKE_WEIGHTS, closeness))
    return speed_m_s * max(0.0, 1.0 - brake), 2.0 * turn


def main():
    rospy.init_node("wander")
    robot = rospy.get_param("~robot", "ePuck0")
    speed = float(rospy.get_param("~speed_m_s", 0.06))
    closeness = [0.0] * 8

    def on_range(msg, k):
        if msg.max_range > 0.0 and math.isfinite(msg.range):
            closeness[k] = max(0.0, 1.0 - msg.range / msg.max_range)
    subs = [rospy.Subscriber(f"/{robot}/proximity{k}", Range, on_range, k, queue_size=1)
            for k in range(8)]
    pub = rospy.Publisher(f"/{robot}/cmd_vel", Twist, queue_size=1)
    rate = rospy.Rate(float(rospy.get_param("~rate_hz", 20.0)))
    while not rospy.is_shutdown():
        cmd = Twist()
        cmd.linear.x, cmd.angular.z = command(closeness, speed)
        pub.publish(cmd)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    del subs
    return 0

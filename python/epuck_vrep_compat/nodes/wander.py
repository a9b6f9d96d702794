"""Braitenberg obstacle avoidance from the eight IR ``Range`` topics: a leader for the demo.

Each sensor's closeness ``1 - range / max_range`` pushes the wheels away from what it sees.
One command per set of readings: when all eight sensors have reported the same stamp (one
step of the simulator, one sensor cycle of the robot), the node publishes ``cmd_vel`` from
them. So it answers every step exactly once, whatever the real-time factor, and in the
experiment runner's lock-step a run is the same run every time.
Parameters: ``~robot`` (ePuck0), ``~speed_m_s`` (0.06).
"""
import math
import threading

import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Range

from epuck_vrep_compat.compat.epuck_names import PROXIMITY_COUNT, VREP

# Per sensor: weight of its closeness on the turn rate (+ = turn left). Front-right sensors
# (0, 1, 2) turn left, front-left (5, 6, 7) turn right, rear ones hardly matter.
TURN_WEIGHTS = (2.0, 1.5, 0.6, 0.1, -0.1, -0.6, -1.5, -2.0)
BRAKE_WEIGHTS = (0.6, 0.3, 0.0, 0.0, 0.0, 0.0, 0.3, 0.6)


def command(closeness, speed_m_s):
    turn = sum(w * c for w, c in zip(TURN_WEIGHTS, closeness))
    brake = sum(w * c for w, c in zip(BRAKE_WEIGHTS, closeness))
    return speed_m_s * max(0.0, 1.0 - brake), 2.0 * turn


class Wanderer:
    """The readings of one sensor cycle, and the command once all eight are in."""

    def __init__(self, speed_m_s, publisher):
        self.speed_m_s, self.publisher = speed_m_s, publisher
        self.closeness = [0.0] * 8
        self.stamps = [None] * 8
        self.last = None
        self.lock = threading.Lock()

    def on_range(self, msg, k):
        with self.lock:
            if msg.max_range > 0.0 and math.isfinite(msg.range):
                self.closeness[k] = max(0.0, 1.0 - msg.range / msg.max_range)
            self.stamps[k] = msg.header.stamp
            stamp = self.stamps[0]
            if stamp == self.last or any(s != stamp for s in self.stamps):
                return
            self.last = stamp
            cmd = Twist()
            cmd.linear.x, cmd.angular.z = command(self.closeness, self.speed_m_s)
            self.publisher.publish(cmd)


def main():
    rospy.init_node("wander")
    robot = rospy.get_param("~robot", VREP.robot_name(0))
    speed = float(rospy.get_param("~speed_m_s", 0.06))
    pub = rospy.Publisher(VREP.topic(robot, "cmd_vel"), Twist, queue_size=1)
    wanderer = Wanderer(speed, pub)
    subs = [rospy.Subscriber(VREP.topic(robot, f"proximity{k}"), Range, wanderer.on_range, k,
                             queue_size=8) for k in range(PROXIMITY_COUNT)]
    rospy.spin()
    del subs
    return 0

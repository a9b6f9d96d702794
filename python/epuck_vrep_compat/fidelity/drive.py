"""The ``paper_scenario`` node: drives one robot through a section 4.1 scenario.

Publishes the scenario's forward speed on the robot's ``cmd_vel`` at 20 Hz of simulated time
from the first ``/clock`` on, for the scenario's drive time, then zero for as long as it runs.
Parameters: ``~scenario`` (rest | straight | wall), ``~cmd_vel`` (/ePuck0/cmd_vel).
"""
import sys

import rospy
from geometry_msgs.msg import Twist

from epuck_vrep_compat.compat.epuck_names import VREP
from epuck_vrep_compat.fidelity.scenarios import SCENARIOS


def main():
    rospy.init_node("paper_scenario")
    name = rospy.get_param("~scenario", "rest")
    if name not in SCENARIOS:
        rospy.logfatal(f"parameter '~scenario' must be one of {sorted(SCENARIOS)}, got {name!r}")
        return 2
    scenario = SCENARIOS[name]
    cmd_vel = rospy.get_param("~cmd_vel", VREP.topic(VREP.robot_name(0), "cmd_vel"))
    pub = rospy.Publisher(cmd_vel, Twist, queue_size=10)
    rate = rospy.Rate(20.0)
    start = None
    while not rospy.is_shutdown():
        now = rospy.get_time()
        if now > 0.0:
            start = now if start is None else start
            cmd = Twist()
            cmd.linear.x = scenario.speed_at(now - start)
            pub.publish(cmd)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    return 0


if __name__ == "__main__":
    sys.exit(main())

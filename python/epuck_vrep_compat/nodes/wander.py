"""Braitenberg obstacle avoidance from the eight IR ``Range`` topics: a leader for the demo.

Each sensor's closeness ``1 - range / max_range`` pushes the wheels away from what it sees.
One command per sensor cycle (``ir_cycle``): it answers every step exactly once, so in the
experiment runner's lock-step a run is the same run every time.
Parameters: ``~robot`` (ePuck0), ``~speed_m_s`` (0.06).
"""
import rospy

from epuck_vrep_compat.nodes import ir_cycle

# Per sensor: weight of its closeness on the turn rate (+ = turn left). Front-right sensors
# (0, 1, 2) turn left, front-left (5, 6, 7) turn right, rear ones hardly matter.
TURN_WEIGHTS = (2.0, 1.5, 0.6, 0.1, -0.1, -0.6, -1.5, -2.0)
BRAKE_WEIGHTS = (0.6, 0.3, 0.0, 0.0, 0.0, 0.0, 0.3, 0.6)


def command(closeness, speed_m_s):
    turn = sum(w * c for w, c in zip(TURN_WEIGHTS, closeness))
    brake = sum(w * c for w, c in zip(BRAKE_WEIGHTS, closeness))
    return speed_m_s * max(0.0, 1.0 - brake), 2.0 * turn


def main():
    def make_control():
        speed_m_s = float(rospy.get_param("~speed_m_s", 0.06))
        return lambda ranges, max_ranges: command(ir_cycle.closeness(ranges, max_ranges),
                                                  speed_m_s)
    return ir_cycle.run("wander", make_control)

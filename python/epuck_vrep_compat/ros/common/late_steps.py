"""Steps a node took in lock-step without waiting for something it waits for (an answer or an
input that did not come within a time-out of wall time): a run whose outcome may so have
depended on the machine's speed says so in its row (``late_steps``).

Each node counts its own in the parameter ``/experiment/late_steps/<node name>``, a total since
it started (:class:`LateSteps`); the experiment's probe adds up the change over a run
(:func:`total`). The simulator's lock-step counts a step taken without a watched robot's
answer while that robot's client is still connected (a dead one changes nothing a wait could
have changed); the operator tracker an input given up, the supervisor an estimate or a frame
given up. rospy only: the simulator and the client nodes share it.
"""
import rospy

from epuck_vrep_compat.compat.topics import LATE_STEPS_PARAM


class LateSteps:
    """One node's count, written to its parameter at each change (rare: a step that went on
    without waiting)."""

    def __init__(self):
        self.count = 0

    def add(self, steps: int = 1):
        self.count += steps
        if not rospy.core.is_initialized():
            return                  # not a node (a unit test): nobody to tell
        try:
            rospy.set_param(f"{LATE_STEPS_PARAM}/{rospy.get_name().strip('/')}", self.count)
        except (OSError, rospy.ROSException):
            pass                    # no master to tell: no experiment reads it either


def total(value=None) -> int:
    """Every node's count added up (``value``: the parameter's, read now when None)."""
    if value is None:
        try:
            value = rospy.get_param(LATE_STEPS_PARAM, {})
        except (OSError, rospy.ROSException):
            return 0
    if isinstance(value, dict):
        return sum(total(v) for v in value.values())
    return int(value) if isinstance(value, (int, float)) else 0

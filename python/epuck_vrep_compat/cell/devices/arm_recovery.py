"""An arm whose physics diverged is put back where it was before the step.

pybullet's solver can answer a step with NaN joint states for a whole robot (it did for a
mecanum wheel left at 1e308 rad and then driven by velocity); every later step would then fail on
the non-finite link poses, and a stop would not help if the NaN stayed in pybullet. Every request
is checked before it reaches the arm, so a divergence is a bug: the cell puts the arm back to its
state before the step, at rest and holding its joints, finishes the step with it, and reports it
(the step raises: the node logs it and pauses; starting again steps on from a finite state).
"""
import numpy as np


def checkpoint(arm):
    """What an arm is put back to: (joint positions, base x, y, yaw, base height)."""
    return arm.q.copy(), arm.base_xy_yaw.copy(), arm.base_z


def diverged(arm) -> bool:
    """True when the arm's state, as last read from pybullet, holds a non-finite number."""
    return not all(np.all(np.isfinite(a)) for a in (
        arm.q, arm.qd, arm.base_xy_yaw, arm.twist, arm.link_position, arm.link_quat))


def recover_diverged(arms, saved, time_s: float):
    """Each arm that diverged back to its checkpoint (``saved``, one per arm), or to its start
    if even that does not hold; the report of what happened, or None when nothing did."""
    names = []
    for arm, before in zip(arms, saved):
        if not diverged(arm):
            continue
        names.append(arm.spec.name)
        q, base_xy_yaw, base_z = before
        arm.hold_at(base_xy_yaw, base_z, q)
        if diverged(arm):
            arm.reset()
    if not names:
        return None
    return (f"the physics of {', '.join(names)} diverged at t={time_s:.3f} s (non-finite joint "
            "state, a bug: every request is checked before it reaches the arms); put back to "
            "the state before the step, at rest")

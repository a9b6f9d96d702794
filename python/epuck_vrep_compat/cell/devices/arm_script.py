"""The cell robots' default motions, as the thesis's child scripts: what an arm does until a
client commands it."""
import math

from epuck_vrep_compat.cell.devices.arm_joint import POSITION


def scripted_motion(arm, t: float):
    """Command ``arm`` (an ArticulatedRobot) for time ``t`` of its script: each joint swings
    sinusoidally about the middle of its range (phase-shifted per joint); a mobile base drives
    a square."""
    s = arm.spec
    if s.script == "none":
        return
    w = 2.0 * math.pi / s.script_period_s
    for k, joint in enumerate(arm.joints):
        if joint.cyclic:
            continue
        lower, upper = joint.lower, joint.upper
        if joint.prismatic:
            centre, half = 0.5 * (lower + upper), 0.5 * (upper - lower)
        else:
            centre = min(max(0.0, lower), upper)
            half = min(centre - lower, upper - centre)
            if half < 0.1 * (upper - lower):      # zero at a stop (youBot): mid-range
                centre, half = 0.5 * (lower + upper), 0.5 * (upper - lower)
        arm.command(k, POSITION, centre + s.script_amplitude * half *
                    math.sin(w * t + 0.7 * k), external=False)
    if s.mobile and s.script == "square":
        side = int(t / (0.25 * s.script_period_s)) % 4
        speed = 0.15
        arm.set_twist(*((speed, 0, 0), (0, speed, 0), (-speed, 0, 0), (0, -speed, 0))[side],
                      external=False)

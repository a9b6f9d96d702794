"""The youBot's four-wheel mecanum base: wheel speeds from a body twist and back.

Wheels fl, rl, rr, fr at (±lx, ±ly) from the base centre, radius r, rollers at 45°, each wheel
turning about +y (positive drives forward, ``models/youbot.urdf``). With L = lx + ly and the
wheels' rim speeds v_w = r ω_w (m/s):

    v_fl = vx - vy - L wz        v_fr = vx + vy + L wz
    v_rl = vx + vy - L wz        v_rr = vx - vy + L wz

and, inverting it (least squares over the four wheels, exact when the wheels agree):

    vx = (v_fl + v_rl + v_rr + v_fr) / 4
    vy = (-v_fl + v_rl - v_rr + v_fr) / 4
    wz = (-v_fl - v_rl + v_rr + v_fr) / (4 L)

This is how V-REP's youBot child script drives its base (``simSetJointTargetVelocity`` on the
``rollingJoint_*``), with the sign of our joints' axes.
"""
from typing import Dict, Tuple

# youBot mecanum base: wheel radius and half wheel base + half track (models.md 4.1)
WHEELS = ("fl", "rl", "rr", "fr")
WHEEL_RADIUS_M = 0.0475
WHEEL_LX_PLUS_LY_M = 0.228 + 0.158
MAX_WHEEL_SPEED_M_S = 0.8       # the youBot datasheet's top speed (models.md 4.1)


def wheel_speeds(vx: float, vy: float, wz: float) -> Dict[str, float]:
    """Each wheel's angular velocity [rad/s] for the body twist (vx, vy [m/s], wz [rad/s])."""
    spin = WHEEL_LX_PLUS_LY_M * wz
    rims = {"fl": vx - vy - spin, "rl": vx + vy - spin, "rr": vx - vy + spin,
            "fr": vx + vy + spin}
    return {w: v / WHEEL_RADIUS_M for w, v in rims.items()}


def body_twist(omega: Dict[str, float]) -> Tuple[float, float, float]:
    """The body twist (vx, vy [m/s], wz [rad/s]) of the wheels' angular velocities [rad/s]."""
    fl, rl, rr, fr = (WHEEL_RADIUS_M * float(omega[w]) for w in WHEELS)
    return (0.25 * (fl + rl + rr + fr), 0.25 * (-fl + rl - rr + fr),
            0.25 * (-fl - rl + rr + fr) / WHEEL_LX_PLUS_LY_M)

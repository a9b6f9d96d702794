"""Each robot's ``robot_description`` (URDF), so rviz's RobotModel display draws the e-pucks.

The links carry the profile's frame names (``epuck_robot_0/base_link``, ``ePuck0/base_prox3``,
``epuck_robot_0/base_dist_sens`` ...), so RobotModel needs no TF prefix: it places each link
from the TF tree the simulator broadcasts. Fixed offsets come from the same table as that tree
(:func:`~epuck_vrep_compat.ros.epuck.transforms.robot_child_frames`), so the model and TF
cannot disagree; the wheels are continuous joints turning about their axles.

The parameter sits in the robot's namespace: ``/<robot>/robot_description`` (the driver's
multi-robot launch sets one ``/robot_description`` for all; ours is per robot because the
link names differ), ``/robot_description`` for a robot at the root namespace. It follows
robots loaded and removed at run time.
"""
from xml.sax.saxutils import quoteattr

import numpy as np
import rospy

from epuck_vrep_compat.compat import epuck_names
from epuck_vrep_compat.ros.epuck.transforms import robot_child_frames
from epuck_vrep_compat.ros.face import Face, Step

_WHITE = '<material name="body"><color rgba="0.9 0.9 0.85 1"/></material>'
_DARK = '<material name="wheel"><color rgba="0.15 0.15 0.15 1"/></material>'


def _rpy(q):
    """Roll, pitch, yaw of a quaternion (x, y, z, w)."""
    x, y, z, w = (float(v) for v in q)
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def _origin(xyz, q):
    r, p, y = _rpy(q)
    return (f'<origin xyz="{xyz[0]:.6f} {xyz[1]:.6f} {xyz[2]:.6f}" '
            f'rpy="{r:.6f} {p:.6f} {y:.6f}"/>')


def robot_urdf(profile, sim, index) -> str:
    """The URDF of robot ``index`` with links named as the profile's frames."""
    robot = sim.epucks.robot_names[index]
    model = sim.epucks.model
    base = profile.frame(robot, epuck_names.BASE_FRAME)
    radius, height = model.body_radius_m, model.body_height_m
    parts = [f'<robot name={quoteattr(profile.frame_prefix(robot))}>', _WHITE, _DARK,
             f'<link name={quoteattr(base)}><visual><origin xyz="0 0 {height / 2:.4f}"/>'
             f'<geometry><cylinder radius="{radius}" length="{height}"/></geometry>'
             '<material name="body"/></visual></link>']
    for child, xyz, q in robot_child_frames(profile, sim, index):
        link = profile.frame(robot, child)
        wheel = q is None
        visual = ('<visual><origin rpy="1.570796 0 0"/><geometry><cylinder radius='
                  f'"{model.wheel_radius_m}" length="0.003"/></geometry>'
                  '<material name="wheel"/></visual>' if wheel else "")
        parts.append(f"<link name={quoteattr(link)}>{visual}</link>")
        kind = "continuous" if wheel else "fixed"
        axis = '<axis xyz="0 1 0"/>' if wheel else ""
        parts.append(f'<joint name={quoteattr(link + "_joint")} type="{kind}">'
                     f'<parent link={quoteattr(base)}/><child link={quoteattr(link)}/>'
                     f'{_origin(xyz, (0, 0, 0, 1.0) if wheel else q)}{axis}</joint>')
    parts.append("</robot>")
    return "\n".join(parts)


def description_param(profile, robot_name: str) -> str:
    if robot_name == epuck_names.ROOT_NAMESPACE:
        return "/robot_description"
    return f"/{robot_name}/robot_description"


class DescriptionFace(Face):
    """Sets each robot's ``robot_description`` and deletes a removed robot's."""

    def __init__(self, profile, sim):
        self.profile = profile
        self.sim = sim
        self._set = set()
        self.sync()

    def sync(self):
        names_now = list(self.sim.epucks.robot_names)
        for name in self._set - set(names_now):
            try:
                rospy.delete_param(description_param(self.profile, name))
            except KeyError:
                pass
        for i, name in enumerate(names_now):
            if name not in self._set:
                rospy.set_param(description_param(self.profile, name),
                                robot_urdf(self.profile, self.sim, i))
        self._set = set(names_now)

    def publish(self, step: Step):
        """Nothing per step: the parameter is set once per robot."""

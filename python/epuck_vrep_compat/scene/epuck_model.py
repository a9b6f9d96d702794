"""The e-puck as a scene model: its parts with V-REP's object names, and its physical data.

Part names follow the V-REP model (``ePuck_leftJoint``, ``ePuck_proxSensor0``, ...); copies get
V-REP's suffixes: robot 0 has none, robot k >= 1 has ``#k-1`` (``ePuck_leftJoint#0`` belongs to
``ePuck1``), which is how the V-REP script derives the robot name from its suffix. A model
loaded or pasted while the simulation runs gets, as in V-REP, the suffix one above the largest
suffix in the scene (:func:`next_robot_number`).
The IR sensor mounts come from the C++ core's model, so they are defined once.
"""
import numpy as np

from epuck_vrep_compat._core import EpuckModel
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.epuck_names import MODEL_ROOT_OBJECT, model_object_name
from epuck_vrep_compat.geometry.transforms import (
    IDENTITY_QUAT, quat_from_axis_angle, quat_from_yaw, quat_mul)
from epuck_vrep_compat.scene import registry as reg

WHEEL_Y_M = 0.0265            # half the 53 mm wheel separation
WHEEL_Z_M = 0.020             # axle height = wheel radius
BODY_TOP_Z_M = 0.037          # driver URDF base_to_body_top
CAMERA_POSITION_M = (0.037, 0.0, 0.028)
LED_RING_RADIUS_M = 0.0343    # V-REP model's LED circle
LED_Z_M = 0.0394

# V-REP joints turn about their own z axis: the wheel joints' z is the robot's +y.
_JOINT_QUAT = quat_from_axis_angle((1, 0, 0), -np.pi / 2)
# V-REP proximity and vision sensors look along their own z axis.
_Z_TO_X = quat_from_axis_angle((0, 1, 0), np.pi / 2)
_VISION_QUAT = quat_mul(quat_from_axis_angle((1, 0, 0), np.pi / 2), _Z_TO_X)


def vrep_suffix(index: int) -> str:
    return "" if index == 0 else f"#{index - 1}"


def suffix_number(name: str) -> int:
    """V-REP's suffix number of an object name: k for ``name#k``, -1 for none."""
    _, hash_mark, tail = name.rpartition("#")
    return int(tail) if hash_mark and tail.isascii() and tail.isdigit() else -1


def next_robot_number(object_names) -> int:
    """The robot number k (suffix ``#k-1``) of a model added to a scene holding these names:
    V-REP pastes a model with the suffix one above the largest one in the scene."""
    return max((suffix_number(n) for n in object_names), default=-1) + 2


def default_model() -> EpuckModel:
    return EpuckModel()


def led_positions():
    """Body-frame positions of the 8 ring LEDs, the body LED and the front LED."""
    angles = np.deg2rad([0, -45, -90, -135, 180, 135, 90, 45])
    ring = [(LED_RING_RADIUS_M * np.cos(a), LED_RING_RADIUS_M * np.sin(a), LED_Z_M)
            for a in angles]
    return ring + [(0.0, 0.0, 0.03), (0.031, -0.0125, 0.0285)]


class RobotParts:
    """Handles of one robot's parts, and the frames the ROS faces publish for them."""

    def __init__(self, root, parts):
        self.root = root
        self.parts = parts          # part key -> SceneObject

    def handle(self, key: str) -> int:
        return self.parts[key].handle


def register_epuck(registry: reg.SceneRegistry, model: EpuckModel, index: int,
                   robot_name: str, root_pose_source, wheel_angle_source) -> RobotParts:
    """Register robot ``index``'s objects (suffix ``#index-1``); poses of the root and wheels
    come from the sources. ValueError, with nothing registered, when a name is taken."""
    sfx = vrep_suffix(index)
    root = registry.add(MODEL_ROOT_OBJECT + sfx, vc.OBJECT_SHAPE, vc.WORLD,
                        pose_source=root_pose_source, robot=robot_name, part="root")
    parts = {"root": root}

    def add(key, object_type, position=(0, 0, 0), quat=IDENTITY_QUAT, parent=None, **kwargs):
        parent_handle = root.handle if parent is None else parts[parent].handle
        parts[key] = registry.add(model_object_name(key) + sfx, object_type, parent_handle,
                                  position, quat, robot=robot_name, part=key, **kwargs)

    try:
        _add_parts(add, model, wheel_angle_source)
    except ValueError:            # a name already taken: leave nothing half-registered
        registry.remove(root.handle)
        raise
    return RobotParts(root, parts)


def _add_parts(add, model, wheel_angle_source):
    """Every part but the root, in the V-REP model's order (which fixes the handles)."""
    add("base", vc.OBJECT_DUMMY)
    add("bodyElements", vc.OBJECT_SHAPE)
    for side, sign in (("left", 1.0), ("right", -1.0)):
        add(f"{side}Joint", vc.OBJECT_JOINT, (0.0, sign * WHEEL_Y_M, WHEEL_Z_M), _JOINT_QUAT,
            properties={"joint_type": vc.JOINT_REVOLUTE, "wheel": side})
        add(f"{side}Wheel", vc.OBJECT_SHAPE, parent=f"{side}Joint",
            pose_source=_wheel_pose_source(wheel_angle_source, 0 if side == "left" else 1))
    add("ring", vc.OBJECT_SHAPE, (0.0, 0.0, BODY_TOP_Z_M))
    for i, sensor in enumerate(model.sensors):
        yaw_quat = quat_from_yaw(sensor.yaw_rad)
        position = tuple(sensor.position)
        add(f"proxSensor{i}", vc.OBJECT_PROXIMITY_SENSOR, position,
            quat_mul(yaw_quat, _Z_TO_X), properties={"sensor_index": i})
        add(f"dummy_proxSensor{i}", vc.OBJECT_DUMMY, position, yaw_quat)
    add("camera", vc.OBJECT_VISION_SENSOR, CAMERA_POSITION_M, _VISION_QUAT)
    add("ledLight", vc.OBJECT_LIGHT, (0.0, 0.0, LED_Z_M))


def _wheel_pose_source(wheel_angle_source, column):
    """A wheel turns about its joint's z axis; expressed so that at angle 0 the wheel frame is
    aligned with the robot, and the wheel's frame in base_link is a pure rotation about +y."""
    joint_inverse = _JOINT_QUAT * np.array([-1.0, -1.0, -1.0, 1.0])
    zero = np.zeros(3)

    def pose():
        angle = wheel_angle_source()[column]
        return zero, quat_mul(quat_from_axis_angle((0, 0, 1), angle), joint_inverse)
    return pose

"""simRosGetObjectGroupData's data (VP ``ROS_server::getObjectGroupData``): one kind of data for
every object of a group, appended in object order.

The group is every scene object (``objectType`` 109) or every object of one type (0..107); any
other value is a collection handle in V-REP, and this scene has no collections. V-REP 3.3.0
returns only the group's first object (its ``return(true)`` sits inside the object loop); we
return every object, as V-REP 3.2.1 did, which is what clients that index past element 0 need.
ROS-free: the ``/vrep`` service and the ``get_object_group_data`` stream both call
:func:`group_data`.
"""
import numpy as np

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import compose, vrep_euler_angles
from epuck_vrep_compat.vrep.errors import VrepError

NO_DATA = ((), (), ())        # (ints, floats, strings) of one object


def group_handles(backend, object_type: int):
    """Handles of the group's objects, in handle order."""
    if object_type == vc.APPOBJ_OBJECT:
        return backend.objects(vc.HANDLE_ALL)
    if 0 <= object_type < vc.OBJECT_TYPE_END:
        return backend.objects(object_type)
    raise VrepError(f"object type {object_type} is neither 109 (all objects), an object type "
                    "0..107 nor a collection (the scene defines no collections)")


def _frame(data_type: int) -> int:
    """Even data types 4..12 are relative to the parent, odd ones absolute."""
    return vc.HANDLE_PARENT if data_type % 2 == 0 else vc.WORLD


class _Request:
    """One request's backend and poses: each object's world pose is composed once and shared
    by its descendants (a joint deep in an arm no longer walks the whole chain on its own),
    and a pose relative to the parent is the object's own local pose."""

    def __init__(self, backend):
        self.backend = backend
        self._registry = backend.sim.registry
        self._world = {}

    def pose(self, handle, data_type):
        obj = self._registry.get(handle)
        if _frame(data_type) == vc.HANDLE_PARENT:
            p, q = obj.local_pose()
            return np.asarray(p, dtype=float), np.asarray(q, dtype=float)
        return self._world_pose(obj)

    def _world_pose(self, obj):
        hit = self._world.get(obj.handle)
        if hit is None:
            p, q = obj.local_pose()
            if obj.parent != vc.WORLD:
                p, q = compose(*self._world_pose(self._registry.get(obj.parent)), p, q)
            hit = self._world[obj.handle] = (np.asarray(p, dtype=float),
                                             np.asarray(q, dtype=float))
        return hit


def _position_and_euler(req, handle, data_type):
    p, q = req.pose(handle, data_type)
    return list(p) + list(vrep_euler_angles(q))


def _names(req, handle, _):
    return (), (), (req.backend.object_name(handle),)


def _types(req, handle, _):
    return (req.backend.object_type(handle),), (), ()


def _parents(req, handle, _):
    return (req.backend.parent(handle),), (), ()


def _positions(req, handle, data_type):
    return (), list(req.pose(handle, data_type)[0]), ()


def _eulers(req, handle, data_type):
    return (), vrep_euler_angles(req.pose(handle, data_type)[1]), ()


def _quaternions(req, handle, data_type):
    return (), list(req.pose(handle, data_type)[1]), ()


def _poses_euler(req, handle, data_type):
    return (), _position_and_euler(req, handle, data_type), ()


def _poses_quaternion_as_plugin(req, handle, data_type):
    # The plugin's bug, reproduced: it fills the "quaternion" with simGetObjectOrientation, so
    # clients get 3 Euler angles and a fourth, never written value (0.0 here) instead of a
    # quaternion.
    return (), _position_and_euler(req, handle, data_type) + [0.0], ()


def _proximity(req, handle, _):
    if req.backend.object_type(handle) != vc.OBJECT_PROXIMITY_SENSOR:
        return (-1, -1), [0.0] * 6, ()
    state, point, detected, normal = req.backend.proximity(handle)
    return (int(state), int(detected)), list(point) + list(normal), ()


def _force(req, handle, _):
    if req.backend.object_type(handle) != vc.OBJECT_FORCE_SENSOR:
        return (-1,), [0.0] * 6, ()
    state, force, torque = req.backend.read_force_sensor(handle)
    return (int(state),), list(force) + list(torque), ()


def _joint_state(req, handle, _):
    if req.backend.object_type(handle) != vc.OBJECT_JOINT:
        return (), [0.0, 0.0], ()
    position, _velocity, effort = req.backend.joint_state(handle)
    return (), [position, effort], ()


def _joint_properties(req, handle, _):
    if req.backend.object_type(handle) != vc.OBJECT_JOINT:
        return (-1, -1), [0.0, 0.0], ()
    joint = req.backend.joint(handle)
    mode = joint.mode | (vc.JOINTMODE_HYBRID_FLAG if getattr(joint, "hybrid", False) else 0)
    span = -1.0 if joint.cyclic else joint.range_span
    return (joint.joint_type, mode), [joint.range_min, span], ()


def _linear_velocity(req, handle, _):
    return (), list(req.backend.velocity(handle)[0]), ()


def _angular_velocity(req, handle, _):
    return (), list(req.backend.velocity(handle)[1]), ()


def _twist(req, handle, _):
    linear, angular = req.backend.velocity(handle)
    return (), list(linear) + list(angular), ()


_READERS = {
    vc.GROUP_DATA_NAMES: _names,
    vc.GROUP_DATA_TYPES: _types,
    vc.GROUP_DATA_PARENTS: _parents,
    vc.GROUP_DATA_ABS_POSITION: _positions,
    vc.GROUP_DATA_REL_POSITION: _positions,
    vc.GROUP_DATA_ABS_EULER: _eulers,
    vc.GROUP_DATA_REL_EULER: _eulers,
    vc.GROUP_DATA_ABS_QUATERNION: _quaternions,
    vc.GROUP_DATA_REL_QUATERNION: _quaternions,
    vc.GROUP_DATA_ABS_POSE_EULER: _poses_euler,
    vc.GROUP_DATA_REL_POSE_EULER: _poses_euler,
    vc.GROUP_DATA_ABS_POSE_QUATERNION: _poses_quaternion_as_plugin,
    vc.GROUP_DATA_REL_POSE_QUATERNION: _poses_quaternion_as_plugin,
    vc.GROUP_DATA_PROXIMITY: _proximity,
    vc.GROUP_DATA_FORCE: _force,
    vc.GROUP_DATA_JOINT_STATE: _joint_state,
    vc.GROUP_DATA_JOINT_PROPERTIES: _joint_properties,
    vc.GROUP_DATA_LINEAR_VELOCITY: _linear_velocity,
    vc.GROUP_DATA_ANGULAR_VELOCITY: _angular_velocity,
    vc.GROUP_DATA_TWIST: _twist,
}


def group_data(backend, object_type: int, data_type: int):
    """(handles, ints, floats, strings) of a group; VrepError for an unknown object or data
    type (V-REP would answer an unknown data type with the handles alone)."""
    reader = _READERS.get(data_type)
    if reader is None:
        raise VrepError(f"data type {data_type} is not one of 0..19")
    handles = group_handles(backend, object_type)
    request = _Request(backend)
    ints, floats, strings = [], [], []
    for handle in handles:
        i, f, s = reader(request, handle, data_type)
        ints.extend(int(v) for v in i)
        floats.extend(float(v) for v in f)
        strings.extend(s)
    return handles, ints, floats, strings


__all__ = ["group_data", "group_handles", "vrep_euler_angles"]

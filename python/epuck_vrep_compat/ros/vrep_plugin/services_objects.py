"""``simRos*`` handlers for scene objects: handles, lists, parent/child, group data, poses,
selection, object parameters, and adding and removing models (VP ``ROS_server.cpp``, one
V-REP call each).

Every handler is ``handler(backend, req, errors) -> response``: it raises ``VrepError`` for
V-REP's failure answer, or appends to ``errors`` what V-REP reports while still answering (an
unknown handle among several). A handler with slow work that touches no simulation state
(reading a file) is a :class:`Prepared`: its ``prepare(backend, req)`` runs before the
simulation lock is taken, and ``handler(backend, req, errors, prepared)`` under it.
"""
from typing import Callable, NamedTuple

import rospy
from vrep_common import srv

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.ros.messages import time_stamp
from epuck_vrep_compat.vrep.backend import VrepError
from epuck_vrep_compat.vrep.group_data import group_data


class Prepared(NamedTuple):
    """A handler in two halves: ``prepare`` outside the simulation lock, ``handler`` under it."""

    prepare: Callable
    handler: Callable


def sim_stamp(backend):
    """Stamps of the /vrep services are simulation time, like /clock."""
    return time_stamp(backend.sim.time_s)


def frame_seq(backend) -> int:
    """V-REP's simulation frame id as a header seq (uint32: -1 before a start)."""
    return backend.control.frame_id & 0xFFFFFFFF


def get_object_handle(backend, req, errors):
    if not req.objectName:
        raise VrepError("object name is empty")
    return srv.simRosGetObjectHandleResponse(handle=backend.object_handle(req.objectName))


def get_objects(backend, req, errors):
    # V-REP counts with simGetObjects(index, type) until it fails: a bad type answers 0 objects.
    if req.objectType == vc.APPOBJ_OBJECT:
        errors.append(f"object type {req.objectType} is not valid (use -2 for all objects)")
        return srv.simRosGetObjectsResponse(result=0, handles=[])
    try:
        handles = backend.objects(req.objectType)
    except VrepError as e:
        errors.append(str(e))
        handles = []
    return srv.simRosGetObjectsResponse(result=len(handles), handles=handles)


def get_object_parent(backend, req, errors):
    return srv.simRosGetObjectParentResponse(parentHandle=backend.parent(req.handle))


def get_object_child(backend, req, errors):
    return srv.simRosGetObjectChildResponse(childHandle=backend.child(req.handle, req.index))


def get_object_group_data(backend, req, errors):
    handles, ints, floats, strings = group_data(backend, req.objectType, req.dataType)
    return srv.simRosGetObjectGroupDataResponse(handles=handles, intData=ints,
                                                floatData=floats, strings=strings)


def get_object_pose(backend, req, errors):
    position, quat = backend.pose(req.handle, req.relativeToObjectHandle)
    res = srv.simRosGetObjectPoseResponse(result=1)
    res.pose.header.seq = frame_seq(backend)
    res.pose.header.stamp = sim_stamp(backend)
    p, o = res.pose.pose.position, res.pose.pose.orientation
    p.x, p.y, p.z = (float(v) for v in position)
    o.x, o.y, o.z, o.w = (float(v) for v in quat)
    return res


def _position(point):
    return [point.x, point.y, point.z]


def _quaternion(q):
    return [q.x, q.y, q.z, q.w]


def set_object_pose(backend, req, errors):
    backend.set_pose(req.handle, req.relativeToObjectHandle, _position(req.pose.position),
                     _quaternion(req.pose.orientation))
    return srv.simRosSetObjectPoseResponse(result=1)


def set_object_position(backend, req, errors):
    backend.set_pose(req.handle, req.relativeToObjectHandle, position=_position(req.position))
    return srv.simRosSetObjectPositionResponse(result=1)


def set_object_quaternion(backend, req, errors):
    backend.set_pose(req.handle, req.relativeToObjectHandle, quat=_quaternion(req.quaternion))
    return srv.simRosSetObjectQuaternionResponse(result=1)


def get_object_selection(backend, req, errors):
    return srv.simRosGetObjectSelectionResponse(handles=backend.selection())


def set_object_selection(backend, req, errors):
    for handle in backend.set_selection(req.handles):
        errors.append(f"object handle {handle} does not exist; not selected")
    return srv.simRosSetObjectSelectionResponse(result=len(backend.selection()))


def get_object_int_parameter(backend, req, errors):
    value = backend.object_int_parameter(req.handle, req.parameterID)
    return srv.simRosGetObjectIntParameterResponse(result=1, parameterValue=int(value))


def get_object_float_parameter(backend, req, errors):
    value = backend.object_float_parameter(req.handle, req.parameterID)
    return srv.simRosGetObjectFloatParameterResponse(result=1, parameterValue=float(value))


def _set_object_parameter(backend, req, errors):
    backend.object_type(req.handle)              # an unknown handle is reported as such
    raise VrepError(f"parameter {req.parameter} of object {req.handle} cannot be set in this "
                    "simulator")


def read_model(backend, req):
    """simLoadModel's first half, outside the simulation lock: read and check the file."""
    return backend.read_model(req.fileName)


def load_model(backend, req, errors, model):
    """simLoadModel returns the base handle; the plugin reads it back as the last selected
    object, so the new base ends up selected. ``model``: the file :func:`read_model` read."""
    parts = backend.load_model(req.fileName, model)
    base = parts.root
    backend.set_selection([base.handle])
    rospy.loginfo("simRosLoadModel: '%s' loaded as robot %s (base '%s', handle %d)",
                  req.fileName, base.robot, base.name, base.handle)
    return srv.simRosLoadModelResponse(result=base.handle, baseHandle=base.handle)


def copy_paste_objects(backend, req, errors):
    """The result is how many objects were copied; the handles are every new object's."""
    copied, handles = backend.copy_paste(req.objectHandles)
    if handles:
        rospy.loginfo("simRosCopyPasteObjects: %d robot(s) pasted: %s", copied, ", ".join(
            backend.object_name(h) for h in handles if backend.parent(h) == vc.WORLD))
    return srv.simRosCopyPasteObjectsResponse(result=copied, newObjectHandles=handles)


def _remover(service, response_class, count):
    """simRemoveObject answers 1, simRemoveModel the number of objects removed."""
    def handler(backend, req, errors):
        name = backend.object_name(req.handle)
        removed = backend.remove_object(req.handle)
        rospy.loginfo("%s: '%s' removed (%d objects)", service, name, len(removed))
        return response_class(result=len(removed) if count else 1)
    return handler


HANDLERS = {
    "simRosLoadModel": Prepared(read_model, load_model),
    "simRosCopyPasteObjects": copy_paste_objects,
    "simRosRemoveModel": _remover("simRosRemoveModel", srv.simRosRemoveModelResponse, True),
    "simRosRemoveObject": _remover("simRosRemoveObject", srv.simRosRemoveObjectResponse, False),
    "simRosGetObjectHandle": get_object_handle,
    "simRosGetObjects": get_objects,
    "simRosGetObjectParent": get_object_parent,
    "simRosGetObjectChild": get_object_child,
    "simRosGetObjectGroupData": get_object_group_data,
    "simRosGetObjectPose": get_object_pose,
    "simRosSetObjectPose": set_object_pose,
    "simRosSetObjectPosition": set_object_position,
    "simRosSetObjectQuaternion": set_object_quaternion,
    "simRosGetObjectSelection": get_object_selection,
    "simRosSetObjectSelection": set_object_selection,
    "simRosGetObjectIntParameter": get_object_int_parameter,
    "simRosGetObjectFloatParameter": get_object_float_parameter,
    "simRosSetObjectIntParameter": _set_object_parameter,
    "simRosSetObjectFloatParameter": _set_object_parameter,
}

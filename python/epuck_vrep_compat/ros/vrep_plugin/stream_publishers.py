"""What each publisher stream command of the legacy plugin publishes (V-REP 3.3.0's
``ROS_server::launchPublisher`` and ``streamAllData``), except the sensor streams, which are in
:mod:`stream_sensors`.

A :class:`PublisherKind` says how one command behaves:
* ``check(backend, aux)`` runs when the stream is enabled, where the plugin validated the target;
  a :class:`VrepError` means no topic ("Topic could not be published.");
* ``build(step, aux)`` makes this step's message, ``None`` when there is nothing to publish
  (a signal that is absent, a sensor that detects nothing); a :class:`VrepError` ends the stream,
  as the plugin removed a publisher whose target disappeared;
* ``probe(backend, aux)``, for the costly kinds, replaces ``build`` while nobody listens, so a
  stream still ends when its target goes;
* ``always``: built even while nobody listens, because building has a side effect.
``msg_class`` None marks get_transform, whose transforms go out on ``/tf``.
"""
import struct
from dataclasses import dataclass
from typing import Callable, Optional

import rospy
from geometry_msgs.msg import Point32, PoseStamped, TransformStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, Int32, Int32MultiArray, String, UInt8
from vrep_common.msg import ObjectGroupData

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.frames import WORLD_FRAME
from epuck_vrep_compat.ros.transport.wire import WireMessage
from epuck_vrep_compat.ros.vrep_plugin.services_devices import fill_joint_state
from epuck_vrep_compat.ros.vrep_plugin.services_objects import frame_seq
from epuck_vrep_compat.vrep.backend import VrepError
from epuck_vrep_compat.vrep.group_data import group_data


@dataclass(frozen=True)
class PublisherKind:
    """How one publisher stream command behaves (see the module's docstring)."""

    name: str
    msg_class: Optional[type]
    build: Callable
    check: Optional[Callable] = None
    probe: Optional[Callable] = None
    always: bool = False


class StreamStep:
    """What the publisher streams share in one step: stamp, frame id (header.seq), frames."""

    def __init__(self, backend, frames, secs: int, nsecs: int):
        self.backend = backend
        self.frames = frames
        self.stamp = rospy.Time(secs, nsecs)
        self.seq = frame_seq(backend)                   # V-REP's simulation frame id

    def object_frame(self, handle: int) -> str:
        return self.frames.frame_id(self.backend.object_name(handle))


# --- helpers shared with the sensor streams -------------------------------------------------
def signal_bytes(value) -> bytes:
    """A string signal's bytes (V-REP's string signals are byte buffers)."""
    return bytes(value) if isinstance(value, (bytes, bytearray)) else str(value).encode("utf-8")


def string_signal(backend, name: str) -> Optional[bytes]:
    """The bytes of a string signal, or None when it is absent."""
    try:
        return signal_bytes(backend.signal("string", name))
    except VrepError:
        return None


def packed_floats(data: bytes):
    """The float32 values packed in a string signal (V-REP's simPackFloats); a trailing
    partial float is ignored, as the plugin's integer division does."""
    count = len(data) // 4
    return struct.unpack_from(f"<{count}f", data)


def raw_string(data: bytes) -> WireMessage:
    """A std_msgs/String carrying bytes as they are (roscpp's std::string; genpy would insist on
    UTF-8)."""
    return WireMessage(String, struct.pack("<I", len(data)) + data)


def set_header(header, step, frame_id="", seq=0):
    header.seq = seq
    header.stamp = step.stamp
    header.frame_id = frame_id


# --- objects, joints, poses ------------------------------------------------------------------
def _check_joint(backend, aux):
    if aux.int1 != vc.HANDLE_ALL:
        backend.joint(aux.int1)


def _joint_state(step, aux):
    msg = JointState()
    set_header(msg.header, step, seq=step.seq)
    fill_joint_state(step.backend, msg, aux.int1)
    return msg


def _check_pose(backend, aux):
    backend.pose(aux.int1, aux.int2)


def _object_pose(step, aux):
    position, quat = step.backend.pose(aux.int1, aux.int2)
    msg = PoseStamped()
    set_header(msg.header, step, aux.string, step.seq)      # frame_id = auxString (3.3.0)
    p, o = msg.pose.position, msg.pose.orientation
    p.x, p.y, p.z = (float(v) for v in position)
    o.x, o.y, o.z, o.w = (float(v) for v in quat)
    return msg


def _transform(step, aux):
    backend = step.backend
    position, quat = backend.pose(aux.int1, aux.int2)
    parent = backend.parent(aux.int1) if aux.int2 == vc.HANDLE_PARENT else aux.int2
    parent_name = WORLD_FRAME if parent == vc.WORLD else backend.object_name(parent)
    child_frame, parent_frame = step.frames.transform_frames(
        backend.object_name(aux.int1), parent_name, aux.string)
    msg = TransformStamped()
    set_header(msg.header, step, parent_frame)
    msg.child_frame_id = child_frame
    t, r = msg.transform.translation, msg.transform.rotation
    t.x, t.y, t.z = (float(v) for v in position)
    r.x, r.y, r.z, r.w = (float(v) for v in quat)
    return msg


def _check_object(backend, aux):
    backend.object_type(aux.int1)


def _object_parent(step, aux):
    return Int32(step.backend.parent(aux.int1))


def _objects(step, aux):
    try:
        handles = step.backend.objects(aux.int1)
    except VrepError:
        handles = []                        # simGetObjects finds nothing of an invalid type
    return Int32MultiArray(data=handles)


def _object_selection(step, aux):
    return Int32MultiArray(data=step.backend.selection())


def _group_data(step, aux):
    handles, ints, floats, strings = group_data(step.backend, aux.int1, aux.int2)
    if not handles:                         # 3.3.0 reports an empty group as a failure
        raise VrepError(f"object group {aux.int1} is empty")
    msg = ObjectGroupData()
    msg.handles.data = list(handles)
    msg.intData.data = list(ints)
    msg.floatData.data = [float(v) for v in floats]
    msg.stringData.data = "".join(s + "\0" for s in strings)
    return msg


# --- parameters ------------------------------------------------------------------------------
def _parameter(name, getter, msg_class, to_message):
    def read(backend, aux):
        return getattr(backend, getter)(aux.int1)

    def build(step, aux):
        return to_message(read(step.backend, aux))
    return PublisherKind(name, msg_class, build, check=read)


def _object_parameter(name, getter, msg_class):
    def read(backend, aux):
        return getattr(backend, getter)(aux.int1, aux.int2)

    def build(step, aux):
        return msg_class(read(step.backend, aux))
    return PublisherKind(name, msg_class, build, check=read)


def _point32(values):
    return Point32(*(float(v) for v in values[:3]))


# --- signals ---------------------------------------------------------------------------------
def _number_signal(name, kind, msg_class):
    def build(step, aux):
        try:
            return msg_class(step.backend.signal(kind, aux.string))
        except VrepError:
            return None                     # publish only while the signal exists
    return PublisherKind(name, msg_class, build)


def _string_signal(step, aux):
    data = string_signal(step.backend, aux.string)
    return None if data is None else raw_string(data)


def _get_and_clear_string_signal(step, aux):
    msg = _string_signal(step, aux)
    if msg is not None:
        step.backend.clear_signal("string", aux.string)
    return msg


GENERAL_PUBLISHERS = {
    vc.STRMCMD_GET_JOINT_STATE: PublisherKind(
        "get_joint_state", JointState, _joint_state, check=_check_joint),
    vc.STRMCMD_GET_OBJECT_POSE: PublisherKind(
        "get_object_pose", PoseStamped, _object_pose, check=_check_pose),
    vc.STRMCMD_GET_TRANSFORM: PublisherKind(
        "get_transform", None, _transform, check=_check_pose),
    vc.STRMCMD_GET_OBJECT_PARENT: PublisherKind(
        "get_object_parent", Int32, _object_parent, check=_check_object),
    vc.STRMCMD_GET_OBJECTS: PublisherKind("get_objects", Int32MultiArray, _objects),
    vc.STRMCMD_GET_OBJECT_SELECTION: PublisherKind(
        "get_object_selection", Int32MultiArray, _object_selection),
    vc.STRMCMD_GET_OBJECT_GROUP_DATA: PublisherKind(
        "get_object_group_data", ObjectGroupData, _group_data),
    vc.STRMCMD_GET_ARRAY_PARAMETER: _parameter(
        "get_array_parameter", "array_parameter", Point32, _point32),
    vc.STRMCMD_GET_BOOLEAN_PARAMETER: _parameter(
        "get_boolean_parameter", "boolean_parameter", UInt8, lambda v: UInt8(int(bool(v)))),
    vc.STRMCMD_GET_FLOATING_PARAMETER: _parameter(
        "get_floating_parameter", "floating_parameter", Float32, lambda v: Float32(float(v))),
    vc.STRMCMD_GET_INTEGER_PARAMETER: _parameter(
        "get_integer_parameter", "integer_parameter", Int32, lambda v: Int32(int(v))),
    vc.STRMCMD_GET_STRING_PARAMETER: _parameter(
        "get_string_parameter", "string_parameter", String, lambda v: String(str(v))),
    vc.STRMCMD_GET_OBJECT_FLOAT_PARAMETER: _object_parameter(
        "get_object_float_parameter", "object_float_parameter", Float32),
    vc.STRMCMD_GET_OBJECT_INT_PARAMETER: _object_parameter(
        "get_object_int_parameter", "object_int_parameter", Int32),
    vc.STRMCMD_GET_FLOAT_SIGNAL: _number_signal("get_float_signal", "float", Float32),
    vc.STRMCMD_GET_INTEGER_SIGNAL: _number_signal("get_integer_signal", "int", Int32),
    vc.STRMCMD_GET_STRING_SIGNAL: PublisherKind("get_string_signal", String, _string_signal),
    vc.STRMCMD_GET_AND_CLEAR_STRING_SIGNAL: PublisherKind(
        "get_and_clear_string_signal", String, _get_and_clear_string_signal, always=True),
}

"""What each subscriber stream command of the legacy plugin does with a message (V-REP 3.3.0's
``vrepSubscriber.cpp``).

A :class:`SubscriberKind` says how one command behaves:
* ``check(backend, aux)`` runs when the stream is enabled, where the plugin validated the
  target; a :class:`VrepError` means no subscriber (ID -1);
* ``apply(backend, aux, msg)`` acts on a message. :class:`InvalidMessage` (NaN, wrong lengths)
  means the message is ignored; a :class:`VrepError` is a failed V-REP call;
* ``stop_on_error``: where the plugin shut the subscriber down when its call failed. With a
  ``check`` it does so only when the check fails too (the target is gone); without one, on
  any failure (e.g. a parameter that cannot be set).
"""
import math
import struct
from dataclasses import dataclass
from typing import Callable, Optional

from genpy import DeserializationError
from geometry_msgs.msg import Point, Point32, PoseStamped, Quaternion, Twist
from sensor_msgs.msg import Joy
from std_msgs.msg import Float32, Float64, Int32, Int32MultiArray, String, UInt8
from vrep_common.msg import JointSetStateData

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.ros.vrep_plugin.services_devices import JOINT_SET_MODES
from epuck_vrep_compat.ros.vrep_plugin.stream_publishers import signal_bytes
from epuck_vrep_compat.vrep.backend import VrepError

MAX_JOY_VALUES = 4096          # the plugin put axes + buttons on the stack; we refuse silly sizes


class InvalidMessage(ValueError):
    """A message the stream cannot use; it is ignored."""


@dataclass(frozen=True)
class SubscriberKind:
    """How one subscriber stream command behaves (see the module's docstring)."""

    name: str
    msg_class: type
    apply: Callable
    check: Optional[Callable] = None
    stop_on_error: bool = False


class RawString(String):
    """std_msgs/String whose ``data`` stays bytes, as roscpp's std::string (a string signal
    may hold packed floats, which genpy would mangle as UTF-8)."""

    def deserialize(self, data):
        try:
            (length,) = struct.unpack_from("<I", data, 0)
        except struct.error as e:
            raise DeserializationError(e) from None
        self.data = bytes(data[4:4 + length])
        return self


def _finite(*values):
    if not all(math.isfinite(v) for v in values):
        raise InvalidMessage(f"values {values} are not all finite")
    return values


def _text_or_bytes(data: bytes):
    """Signal values stay text when they are text (what the services read and write)."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data


# --- joints ----------------------------------------------------------------------------------
def _check_joint(backend, aux):
    backend.joint(aux.int1)


def _joint_command(what):
    def apply(backend, aux, msg):
        backend.joint_command(aux.int1, what, *_finite(msg.data))
    return apply


def _joint_state(backend, aux, msg):
    handles, modes, values = msg.handles.data, msg.setModes.data, msg.values.data
    if not handles or not len(handles) == len(modes) == len(values):
        raise InvalidMessage(f"handles, setModes and values must be equal-length and non-empty "
                             f"(got {len(handles)}, {len(modes)}, {len(values)})")
    _finite(*values)
    failures = []
    for handle, mode, value in zip(handles, modes, values):
        try:
            what = JOINT_SET_MODES.get(mode)
            if what is None:
                raise VrepError(f"joint {handle}: setMode {mode} is not one of 0..3")
            backend.joint_command(handle, what, value)
        except VrepError as e:
            failures.append(str(e))
    if failures:
        raise VrepError("; ".join(failures))


# --- objects ---------------------------------------------------------------------------------
def _check_object_and_reference(backend, aux):
    backend.object_type(aux.int1)
    if aux.int2 not in (vc.WORLD, vc.HANDLE_PARENT):
        backend.object_type(aux.int2)


def _position(p):
    return _finite(p.x, p.y, p.z)


def _quaternion(q):
    values = _finite(q.x, q.y, q.z, q.w)
    if not any(values):
        raise InvalidMessage("the quaternion is zero")
    return values


def _object_pose(backend, aux, msg):
    pose = msg.pose
    backend.set_pose(aux.int1, aux.int2, _position(pose.position), _quaternion(pose.orientation))


def _object_position(backend, aux, msg):
    backend.set_pose(aux.int1, aux.int2, position=_position(msg))


def _object_quaternion(backend, aux, msg):
    backend.set_pose(aux.int1, aux.int2, quat=_quaternion(msg))


def _object_selection(backend, aux, msg):
    missing = backend.set_selection(msg.data)
    if missing:
        raise VrepError(f"object handles {missing} do not exist; not selected")


# --- parameters ------------------------------------------------------------------------------
def _set_boolean_parameter(backend, aux, msg):
    backend.set_boolean_parameter(aux.int1, bool(msg.data))


def _set_floating_parameter(backend, aux, msg):
    backend.set_floating_parameter(aux.int1, *_finite(msg.data))


def _read_only_parameter(kind):
    def apply(backend, aux, msg):
        raise VrepError(f"{kind} parameter {aux.int1} cannot be set in this simulator")
    return apply


# --- signals ---------------------------------------------------------------------------------
def _set_signal(kind, convert):
    def apply(backend, aux, msg):
        backend.set_signal(kind, aux.string, convert(msg.data))
    return apply


def _append_string_signal(backend, aux, msg):
    try:
        old = signal_bytes(backend.signal("string", aux.string))
    except VrepError:
        old = b""
    backend.set_signal("string", aux.string, _text_or_bytes(old + msg.data))


def _clear_signal(kind):
    def apply(backend, aux, msg):
        backend.clear_signal(kind, aux.string if msg.data == 0 else None)
    return apply


def _twist_command(backend, aux, msg):
    values = _position(msg.linear) + _position(msg.angular)
    backend.set_signal("string", aux.string, struct.pack("<6f", *values))


def _joy_sensor(backend, aux, msg):
    axes, buttons = aux.int1, aux.int2
    if axes < 0 or buttons < 0 or not 0 < axes + buttons <= MAX_JOY_VALUES:
        raise VrepError(f"joy sensor sizes {axes} axes + {buttons} buttons are not valid")
    values = [msg.axes[i] if i < len(msg.axes) else 0.0 for i in range(axes)]
    values += [float(msg.buttons[j]) if j < len(msg.buttons) else 0.0 for j in range(buttons)]
    _finite(*values)
    backend.set_signal("string", aux.string, struct.pack(f"<{len(values)}f", *values))


def _float_value(value):
    return _finite(float(value))[0]


def _status_bar_message(log):
    def apply(backend, aux, msg):
        log(msg.data)
    return apply


def subscriber_kinds(status_bar_log):
    """The supported subscriber commands; ``status_bar_log(text)`` shows a status bar line."""
    joint = dict(check=_check_joint, stop_on_error=True)
    pose = dict(check=_check_object_and_reference, stop_on_error=True)
    return {
        vc.STRMCMD_ADD_STATUS_BAR_MESSAGE: SubscriberKind(
            "add_status_bar_message", String, _status_bar_message(status_bar_log)),
        vc.STRMCMD_SET_OBJECT_SELECTION: SubscriberKind(
            "set_object_selection", Int32MultiArray, _object_selection),
        vc.STRMCMD_SET_JOINT_STATE: SubscriberKind(
            "set_joint_state", JointSetStateData, _joint_state),
        vc.STRMCMD_SET_JOINT_FORCE: SubscriberKind(
            "set_joint_force", Float64, _joint_command("force"), **joint),
        vc.STRMCMD_SET_JOINT_POSITION: SubscriberKind(
            "set_joint_position", Float64, _joint_command("position"), **joint),
        vc.STRMCMD_SET_JOINT_TARGET_POSITION: SubscriberKind(
            "set_joint_target_position", Float64, _joint_command("target_position"), **joint),
        vc.STRMCMD_SET_JOINT_TARGET_VELOCITY: SubscriberKind(
            "set_joint_target_velocity", Float64, _joint_command("target_velocity"), **joint),
        vc.STRMCMD_SET_OBJECT_POSE: SubscriberKind(
            "set_object_pose", PoseStamped, _object_pose, **pose),
        vc.STRMCMD_SET_OBJECT_POSITION: SubscriberKind(
            "set_object_position", Point, _object_position, **pose),
        vc.STRMCMD_SET_OBJECT_QUATERNION: SubscriberKind(
            "set_object_quaternion", Quaternion, _object_quaternion, **pose),
        vc.STRMCMD_SET_ARRAY_PARAMETER: SubscriberKind(
            "set_array_parameter", Point32, _read_only_parameter("array"), stop_on_error=True),
        vc.STRMCMD_SET_BOOLEAN_PARAMETER: SubscriberKind(
            "set_boolean_parameter", UInt8, _set_boolean_parameter, stop_on_error=True),
        vc.STRMCMD_SET_FLOATING_PARAMETER: SubscriberKind(
            "set_floating_parameter", Float32, _set_floating_parameter, stop_on_error=True),
        vc.STRMCMD_SET_INTEGER_PARAMETER: SubscriberKind(
            "set_integer_parameter", Int32, _read_only_parameter("integer"),
            stop_on_error=True),
        vc.STRMCMD_SET_FLOAT_SIGNAL: SubscriberKind(
            "set_float_signal", Float32, _set_signal("float", _float_value)),
        vc.STRMCMD_SET_INTEGER_SIGNAL: SubscriberKind(
            "set_integer_signal", Int32, _set_signal("int", int)),
        vc.STRMCMD_SET_STRING_SIGNAL: SubscriberKind(
            "set_string_signal", RawString, _set_signal("string", _text_or_bytes)),
        vc.STRMCMD_APPEND_STRING_SIGNAL: SubscriberKind(
            "append_string_signal", RawString, _append_string_signal),
        vc.STRMCMD_CLEAR_FLOAT_SIGNAL: SubscriberKind(
            "clear_float_signal", UInt8, _clear_signal("float")),
        vc.STRMCMD_CLEAR_INTEGER_SIGNAL: SubscriberKind(
            "clear_integer_signal", UInt8, _clear_signal("int")),
        vc.STRMCMD_CLEAR_STRING_SIGNAL: SubscriberKind(
            "clear_string_signal", UInt8, _clear_signal("string")),
        vc.STRMCMD_SET_TWIST_COMMAND: SubscriberKind(
            "set_twist_command", Twist, _twist_command, stop_on_error=True),
        vc.STRMCMD_SET_JOY_SENSOR: SubscriberKind(
            "set_joy_sensor", Joy, _joy_sensor, stop_on_error=True),
    }

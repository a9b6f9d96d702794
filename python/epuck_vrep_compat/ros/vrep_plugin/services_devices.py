"""``simRos*`` handlers for joints and sensors (VP ``ROS_server.cpp``).

Same handler shape as :mod:`services_objects`: ``handler(backend, req, errors)``.
"""
import struct

import numpy as np
from vrep_common import srv

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.ros.messages import fill_image
from epuck_vrep_compat.ros.vrep_plugin.services_objects import frame_seq, sim_stamp
from epuck_vrep_compat.vrep.backend import VrepError

_RESULT_AND_COUNT = struct.Struct("<iI")
_COUNT = struct.Struct("<I")

# simRosSetJointState's setModes (and the set_joint_state stream's): which joint call.
JOINT_SET_MODES = {vc.JOINT_SET_POSITION: "position",
                   vc.JOINT_SET_TARGET_POSITION: "target_position",
                   vc.JOINT_SET_TARGET_VELOCITY: "target_velocity",
                   vc.JOINT_SET_FORCE: "force"}


# --- joints ---------------------------------------------------------------------------------
def fill_joint_state(backend, state, handle: int):
    """A sensor_msgs/JointState's names, positions, velocities and efforts for one joint or
    every joint (``sim_handle_all``), as the plugin fills them (service and stream alike)."""
    handles = backend.joints() if handle == vc.HANDLE_ALL else [handle]
    for h in handles:
        position, velocity, effort = backend.joint_state(h)
        state.name.append(backend.object_name(h))
        state.position.append(position)
        state.velocity.append(velocity)
        state.effort.append(effort)


def get_joint_state(backend, req, errors):
    res = srv.simRosGetJointStateResponse(result=1)
    res.state.header.seq = frame_seq(backend)
    res.state.header.stamp = sim_stamp(backend)
    fill_joint_state(backend, res.state, req.handle)
    return res


def _joint_setter(what, field, response_class):
    def handler(backend, req, errors):
        backend.joint_command(req.handle, what, getattr(req, field))
        return response_class(result=1)
    return handler


def set_joint_state(backend, req, errors):
    """Each (handle, mode, value) in turn; the result counts the commands that succeeded."""
    handles, modes, values = list(req.handles), list(req.setModes), list(req.values)
    if not handles or not len(handles) == len(modes) == len(values):
        raise VrepError(f"handles ({len(handles)}), setModes ({len(modes)}) and values "
                        f"({len(values)}) must be non-empty and of equal length")
    done = 0
    for handle, mode, value in zip(handles, modes, values):
        what = JOINT_SET_MODES.get(mode)
        if what is None:
            errors.append(f"joint {handle}: setMode {mode} is not one of 0..3")
            continue
        try:
            backend.joint_command(handle, what, value)
            done += 1
        except VrepError as e:
            errors.append(str(e))
    return srv.simRosSetJointStateResponse(result=done)


# --- sensors --------------------------------------------------------------------------------
def read_proximity_sensor(backend, req, errors):
    state, point, detected, normal = backend.proximity(req.handle)
    return srv.simRosReadProximitySensorResponse(
        result=int(state), detectedPoint=[float(v) for v in point], detectedObject=int(detected),
        normalVector=[float(v) for v in normal])


def get_vision_sensor_image(backend, req, errors):
    mono = bool(req.options & vc.VISION_IMAGE_MONO)
    pixels = backend.vision_image(req.handle, mono)
    res = srv.simRosGetVisionSensorImageResponse(result=1)
    fill_image(res.image, pixels)         # header left default, as the plugin did
    return res


class _DepthBufferResponse(srv.simRosGetVisionSensorDepthBufferResponse):
    """The response with ``buffer`` a float32 array, written to the wire in one copy rather
    than packed float by float (a 640x480 buffer: 14 ms less per call): the array's own
    memory, not a bytes copy of it, goes to the buffer."""

    def serialize(self, buff):
        buff.write(_RESULT_AND_COUNT.pack(self.result, len(self.resolution)))
        buff.write(struct.pack(f"<{len(self.resolution)}i", *self.resolution))
        values = np.ascontiguousarray(self.buffer, dtype="<f4").reshape(-1)
        buff.write(_COUNT.pack(values.size))
        buff.write(values.data)


def get_vision_sensor_depth_buffer(backend, req, errors):
    (width, height), depth = backend.vision_depth(req.handle)
    return _DepthBufferResponse(result=1, resolution=[int(width), int(height)],
                                buffer=depth.reshape(-1))


def read_vision_sensor(backend, req, errors):
    state, packets = backend.read_vision_sensor(req.handle)
    return srv.simRosReadVisionSensorResponse(
        result=int(state), packetData=[float(v) for packet in packets for v in packet],
        packetSizes=[len(packet) for packet in packets])


def read_force_sensor(backend, req, errors):
    state, force, torque = backend.read_force_sensor(req.handle)
    res = srv.simRosReadForceSensorResponse(result=int(state))
    res.force.x, res.force.y, res.force.z = (float(v) for v in force)
    res.torque.x, res.torque.y, res.torque.z = (float(v) for v in torque)
    return res


def read_collision(backend, req, errors):
    return srv.simRosReadCollisionResponse(collisionState=int(backend.read_collision(req.handle)))


def read_distance(backend, req, errors):
    return srv.simRosReadDistanceResponse(result=1,
                                          distance=float(backend.read_distance(req.handle)))


HANDLERS = {
    "simRosGetJointState": get_joint_state,
    "simRosSetJointPosition": _joint_setter("position", "position",
                                            srv.simRosSetJointPositionResponse),
    "simRosSetJointTargetPosition": _joint_setter("target_position", "targetPosition",
                                                  srv.simRosSetJointTargetPositionResponse),
    "simRosSetJointTargetVelocity": _joint_setter("target_velocity", "targetVelocity",
                                                  srv.simRosSetJointTargetVelocityResponse),
    "simRosSetJointForce": _joint_setter("force", "forceOrTorque",
                                         srv.simRosSetJointForceResponse),
    "simRosSetJointState": set_joint_state,
    "simRosReadProximitySensor": read_proximity_sensor,
    "simRosGetVisionSensorImage": get_vision_sensor_image,
    "simRosGetVisionSensorDepthBuffer": get_vision_sensor_depth_buffer,
    "simRosReadVisionSensor": read_vision_sensor,
    "simRosReadForceSensor": read_force_sensor,
    "simRosReadCollision": read_collision,
    "simRosReadDistance": read_distance,
}

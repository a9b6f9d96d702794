"""V-REP's calls on joints and sensors: joint states and commands, proximity, vision, force,
collision and distance readings, through the components of the scene's objects.

A part of :class:`~epuck_vrep_compat.vrep.backend.VrepBackend`. Failures raise
:class:`VrepError` and change nothing.
"""
import math

import numpy as np

from epuck_vrep_compat._core import vrep_depth_buffer
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.devices.components import ComponentError
from epuck_vrep_compat.vrep.errors import VrepError


class VrepDevices:
    """What the scene's joints and sensors do, as V-REP's API calls."""

    def __init__(self, objects):
        """``objects``: the :class:`~epuck_vrep_compat.vrep.objects.VrepObjects` part."""
        self.objects = objects
        self.sim = objects.sim

    # --- joints -------------------------------------------------------------------------
    def joint(self, handle: int):
        obj = self.objects.get(handle)
        joint = obj.properties.get("joint")
        if obj.object_type != vc.OBJECT_JOINT or joint is None:
            raise VrepError(f"object {handle} ('{obj.name}') is not a joint")
        return joint

    def joints(self):
        return [o.handle for o in self.sim.registry.objects() if o.object_type == vc.OBJECT_JOINT]

    def joint_state(self, handle: int):
        joint = self.joint(handle)
        return joint.position(), joint.velocity(), joint.effort()

    def joint_command(self, handle: int, what: str, value: float):
        """``what`` is position, target_position, target_velocity or force."""
        value = float(value)
        if not math.isfinite(value):
            raise VrepError(f"joint {what} {value} is not finite")
        joint = self.joint(handle)
        try:
            getattr(joint, "set_" + what)(value)
        except ComponentError as e:
            raise VrepError(f"joint {handle}: {e}") from None

    # --- sensors ------------------------------------------------------------------------
    def proximity(self, handle: int):
        obj = self.objects.get(handle)
        sensor = obj.properties.get("proximity")
        if sensor is None:
            raise VrepError(f"object {handle} ('{obj.name}') is not a proximity sensor")
        return sensor.read()

    def vision(self, handle: int):
        obj = self.objects.get(handle)
        sensor = obj.properties.get("vision")
        if sensor is None:
            raise VrepError(f"object {handle} ('{obj.name}') is not a vision sensor")
        return sensor

    def vision_image(self, handle: int, mono: bool):
        """Image rows top first (ROS order): rgb (H, W, 3) or grey (H, W) = (r + g + b) / 3."""
        rgb = self.vision(handle).render_rgb()
        if mono:
            return (rgb.astype(np.uint16).sum(axis=2) // 3).astype(np.uint8)
        return rgb

    def vision_depth(self, handle: int):
        """V-REP's depth buffer: (W, H), values 0..1 between the clipping planes, first row =
        bottom of the image (V-REP's order)."""
        sensor = self.vision(handle)
        spec = sensor.spec
        return sensor.resolution, vrep_depth_buffer(sensor.render_depth_kept(), spec.near_m,
                                                    spec.far_m)

    def read_vision_sensor(self, handle: int):
        """simReadVisionSensor: (detection state, auxiliary packets). Our sensors have V-REP's
        default filter, which triggers nothing (state 0) and gives packet 1 only: min, max and
        average of intensity, red, green, blue and depth, all in 0..1. A sensor with a blob
        filter adds packet 2: [blob count, 6, per blob size, orientation, x, y, width, height]."""
        sensor = self.vision(handle)
        rgb, depth = sensor.render()
        colour = rgb.reshape(-1, 3).astype(np.float64) / 255.0
        channels = np.column_stack((colour.mean(axis=1), colour,
                                    _normalised_depth(sensor.spec, depth).reshape(-1)))
        packet = np.concatenate((channels.min(axis=0), channels.max(axis=0),
                                 channels.mean(axis=0)))
        if getattr(sensor, "blob", False):
            # a blob detection filter (the cell's ceiling cameras): packet 2 is its output, and
            # it triggers detection while it finds a blob
            blobs = sensor.blob_packet()
            return int(blobs[0] > 0), [packet.tolist(), blobs.tolist()]
        return 0, [packet.tolist()]

    def read_force_sensor(self, handle: int):
        obj = self.objects.get(handle)
        raise VrepError(f"object {handle} ('{obj.name}') is not a force sensor")

    def read_collision(self, handle: int):
        raise VrepError(f"collision object {handle} does not exist (the scene defines none)")

    def read_distance(self, handle: int):
        raise VrepError(f"distance object {handle} does not exist (the scene defines none)")


def _normalised_depth(spec, depth_m):
    """Depth along the axis [m] to V-REP's 0..1 between the near and far clipping planes, in
    float64 (``vrep_depth_buffer`` is the same in float32, rows bottom first). In place on one
    float64 copy: a 640 x 480 buffer's temporaries cost more than the arithmetic."""
    normalised = depth_m.astype(np.float64)
    normalised -= spec.near_m
    normalised /= spec.far_m - spec.near_m
    return np.clip(normalised, 0.0, 1.0, out=normalised)

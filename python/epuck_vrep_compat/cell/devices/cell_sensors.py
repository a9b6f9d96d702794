"""The cell's vision sensors, as the ``/vrep`` services read them: V-REP's "entity to render"
mask, depth noise and blob filter; and the fixed sensors (laser scanner, ceiling cameras, Kinect)
put into a scene, the cameras at V-REP's 12-value object matrices (the thesis's calibration).
"""
import math

import numpy as np

from epuck_vrep_compat import _core
from epuck_vrep_compat._core import GROUP_ALL, GROUP_DYNAMIC, GROUP_STATIC
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.devices.components import VISION_TO_CAMERA, CameraSpec, VisionSensor
from epuck_vrep_compat.geometry.transforms import (
    pose_from_vrep_matrix, quat_conj, quat_from_axis_angle, quat_from_rpy)

# V-REP vision sensors look along +z with +y up; the Kinect's body frame is x forward, z up:
# vision z = body x, vision x = body y, vision y = body z (the inverse of the vision-to-camera
# turn, since the core's camera frame is the body frame).
BODY_TO_VISION = quat_conj(VISION_TO_CAMERA)


class CellVision(VisionSensor):
    """A vision sensor of the cell: optional render mask (V-REP's "entity to render"), optional
    depth noise (Kinect), and the blob filter's packet (ceiling cameras)."""

    def __init__(self, sim, handle, spec, mask=GROUP_ALL, depth_noise=None, blob=False):
        super().__init__(sim, handle, spec)
        self.mask = mask
        self.depth_noise = depth_noise
        self.blob = blob

    def view(self):
        return super().view() + (self.mask,)

    def _noisy(self, depth):
        """``depth``, a rendering of its own, with the sensor's noise (in place)."""
        if self.depth_noise is None:
            return depth
        return self.depth_noise.apply(depth, self.spec.near_m, self.spec.far_m, out=depth)

    def render(self):
        rgb, depth = self._sim.world.render(*self.view())
        return rgb, self._noisy(depth)

    def render_depth(self, out=None):
        return self._noisy(super().render_depth(out))

    def render_rgb(self):
        if self.depth_noise is not None:
            # every rendering of a noisy sensor draws one image's noise, whatever is read
            return self.render()[0]
        return self._sim.world.render(*self.view(), depth=False)[0]

    def blob_packet(self):
        """V-REP's blob detection filter on what the sensor renders (pixels where a ray hit
        something): [count, 6, size, orientation, x, y, w, h, ...], x and y relative to the
        image, y from the bottom."""
        depth = self.render_depth()
        return np.asarray(_core.detect_blobs((depth < self.spec.far_m).astype(np.uint8)),
                          dtype=float)


def add_laser(s, registry, world, seed: int):
    """The planar laser scanner of ``s`` (a LaserSpec): its housing (50 x 50 x 70 mm around the
    scan origin, which the scan ignores) into the scene. Returns (housing handle, the core's
    LaserScanner seeded with ``seed``)."""
    obj = registry.add(s.name, vc.OBJECT_SHAPE, vc.WORLD, s.position_m,
                       quat_from_axis_angle((0, 0, 1), s.yaw_rad),
                       properties=dict(shape="box", color=(0.1, 0.1, 0.1)))
    world.add_box(obj.handle, np.array([0.025, 0.025, 0.035]), np.asarray(s.position_m),
                  obj.local_quat, (0.1, 0.1, 0.1), GROUP_STATIC)
    scanner = _core.LaserScanner(s.angle_min_rad, s.angle_increment_rad, s.count,
                                 s.range_min_m, s.range_max_m, s.noise_sigma_m,
                                 s.noise_relative, seed)
    return obj.handle, scanner


def add_ceiling_camera(sim, c, operator_name):
    """A ceiling camera of ``c`` (a CameraSpec of the cell file) as a vision sensor in the
    scene; ``operator_name``: the operator's name, or None when there is no operator (a camera
    may render only it). Returns its CellVision."""
    position, quat = pose_from_vrep_matrix(c.matrix)
    obj = sim.registry.add(c.name, vc.OBJECT_VISION_SENSOR, vc.WORLD, position, quat)
    w, h = c.resolution
    # V-REP's perspective angle spans the larger image side
    half = math.tan(0.5 * c.angle_rad) * (h / max(w, h))
    spec = CameraSpec(width=w, height=h, rate_hz=1.0 / sim.step_s,
                      vertical_fov_rad=2.0 * math.atan(half), near_m=c.near_m, far_m=c.far_m)
    mask = GROUP_ALL
    if c.render is not None:
        if operator_name is None or c.render != operator_name:
            raise ValueError(f"camera '{c.name}': render entity '{c.render}' must be "
                             "the operator")
        mask = GROUP_DYNAMIC
    vision = CellVision(sim, obj.handle, spec, mask=mask, blob=bool(c.blob_topics))
    obj.properties["vision"] = vision
    return vision


def add_kinect(sim, k, seed: int):
    """The Kinect of ``k`` (a KinectSpec): its body and two vision sensors (depth with the
    core's DepthNoise seeded with ``seed``, rgb) in the scene. Returns (body handle, depth
    CellVision, rgb CellVision, DepthNoise)."""
    base = sim.registry.add(k.name, vc.OBJECT_SHAPE, vc.WORLD, k.position_m,
                            quat_from_rpy(*k.rpy_rad),
                            properties=dict(shape="box", color=(0.15, 0.15, 0.15)))
    w, h = k.resolution
    vfov = 2.0 * math.atan(math.tan(0.5 * k.horizontal_fov_rad) * h / w)
    spec = CameraSpec(width=w, height=h, rate_hz=30.0, vertical_fov_rad=vfov, near_m=k.near_m,
                      far_m=k.far_m)
    depth_noise = _core.DepthNoise(seed=seed)
    sensors = []
    for suffix, offset_y, noise in (("_depth", -0.0125, depth_noise), ("_rgb", 0.0125, None)):
        obj = sim.registry.add(k.name + suffix, vc.OBJECT_VISION_SENSOR, base.handle,
                               (0.0, offset_y, 0.0), BODY_TO_VISION)
        vision = CellVision(sim, obj.handle, spec, depth_noise=noise)
        obj.properties["vision"] = vision
        sensors.append(vision)
    return base.handle, sensors[0], sensors[1], depth_noise

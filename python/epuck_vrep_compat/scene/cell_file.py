"""The ``cell:`` section of a scene file: articulated robots from URDF, a walking operator (its
own section, :mod:`.operator_file`), and the cell's sensors (ray proximity sensors on robot
links, a planar laser scanner, ceiling cameras with blob detection, a Kinect).

Same rules as the rest of the scene file: lengths in metres, angles in radians, colours RGB in
0..1, and a malformed entry raises :class:`SceneError` naming its key. See
``worlds/merlin_cell.yaml`` for a commented example.
"""
import math
import os
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

from epuck_vrep_compat.compat.topics import CELL_LASER_TOPIC
from epuck_vrep_compat.scene.operator_file import OperatorSpec, parse_operator
from epuck_vrep_compat.scene.validation import (
    SceneError, as_list, color, number, numbers, only, positive)

SCRIPTS = ("none", "sine", "square")


@dataclass
class ArmSpec:
    """An articulated robot of the cell: its URDF, base pose and default motion."""
    name: str                                  # base object name = the URDF's root link
    urdf: str                                  # absolute path
    position_m: Tuple[float, float, float]
    yaw_rad: float = 0.0
    mobile: bool = False                       # base driven by (vx, vy, wz) commands
    script: str = "sine"                       # default motion: none | sine | square (mobile)
    script_period_s: float = 20.0
    script_amplitude: float = 0.5              # fraction of each joint's half range
    color: Tuple[float, float, float] = (0.9, 0.45, 0.1)


@dataclass
class ProxSpec:
    """A ray proximity sensor mounted on a robot's link."""
    name: str
    parent: str                                # link name
    position_m: Tuple[float, float, float]
    rpy_rad: Tuple[float, float, float]        # sensor z = detection axis (V-REP)
    min_range_m: float = 0.02
    max_range_m: float = 0.08


@dataclass
class LaserSpec:
    """The planar laser scanner: its pose, scan geometry, noise and rate."""
    name: str
    position_m: Tuple[float, float, float]
    yaw_rad: float = 0.0
    topic: str = CELL_LASER_TOPIC
    count: int = 682
    angle_min_rad: float = -2.0862138             # (44 - 384) steps of 2*pi/1024
    angle_increment_rad: float = 2.0 * math.pi / 1024.0
    range_min_m: float = 0.02
    range_max_m: float = 5.6
    noise_sigma_m: float = 0.01
    noise_relative: float = 0.01
    rate_hz: float = 10.0


@dataclass
class CameraSpecEntry:
    """A ceiling camera: V-REP's pose matrix, image, clipping, render entity and blob streams."""
    name: str
    matrix: Tuple[float, ...]                  # V-REP's 12 values relative to the floor
    resolution: Tuple[int, int] = (128, 128)
    angle_rad: float = math.radians(80.0)      # perspective angle (larger image side)
    near_m: float = 0.01
    far_m: float = 3.0
    render: Optional[str] = None               # entity to render (None = everything)
    blob_topics: Tuple[str, str] = ()          # float-signal streams of blob x, y


@dataclass
class KinectSpec:
    """The Kinect: its pose, resolution, field of view and depth range."""
    name: str = "kinect"
    position_m: Tuple[float, float, float] = (0.0, 0.0, 1.0)
    rpy_rad: Tuple[float, float, float] = (0.0, 0.0, 0.0)   # x forward, z up (like a robot)
    resolution: Tuple[int, int] = (640, 480)
    horizontal_fov_rad: float = math.radians(57.0)
    near_m: float = 0.5
    far_m: float = 5.0


@dataclass
class CellSpec:
    """The whole ``cell:`` section of a scene file."""
    arms: List[ArmSpec] = field(default_factory=list)
    operator: Optional[OperatorSpec] = None
    proximity: List[ProxSpec] = field(default_factory=list)
    laser: Optional[LaserSpec] = None
    cameras: List[CameraSpecEntry] = field(default_factory=list)
    kinect: Optional[KinectSpec] = None
    substeps: int = 10


def parse_cell(d, where: str, base_dir: str) -> CellSpec:
    if not isinstance(d, dict):
        raise SceneError(f"{where} must be a mapping")
    only(d, {"robots", "operator", "proximity_sensors", "laser", "cameras", "kinect",
              "substeps"}, where)
    cell = CellSpec()
    cell.arms = [_arm(a, f"{where}.robots[{i}]", base_dir)
                 for i, a in enumerate(as_list(d.get("robots", []), f"{where}.robots"))]
    if "operator" in d:
        cell.operator = parse_operator(d["operator"], f"{where}.operator", base_dir)
    cell.proximity = [_prox(p, f"{where}.proximity_sensors[{i}]") for i, p in
                      enumerate(as_list(d.get("proximity_sensors", []),
                                      f"{where}.proximity_sensors"))]
    if "laser" in d:
        cell.laser = _laser(d["laser"], f"{where}.laser")
    cell.cameras = [_camera(c, f"{where}.cameras[{i}]")
                    for i, c in enumerate(as_list(d.get("cameras", []), f"{where}.cameras"))]
    if "kinect" in d:
        cell.kinect = _kinect(d["kinect"], f"{where}.kinect")
    cell.substeps = _count(d.get("substeps", cell.substeps), f"{where}.substeps")
    return cell


def _mapping(d, keys, where):
    if not isinstance(d, dict):
        raise SceneError(f"{where} must be a mapping")
    only(d, keys, where)


def _required(d, key, where):
    if key not in d:
        raise SceneError(f"{where}.{key} is required")
    return d[key]


def _count(v, where) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or v < 1:
        raise SceneError(f"{where} must be a positive integer, got {v!r}")
    return v


def _name(d, where) -> str:
    v = _required(d, "name", where)
    if not isinstance(v, str) or not v:
        raise SceneError(f"{where}.name must be a non-empty string, got {v!r}")
    return v


def _arm(d, where, base_dir) -> ArmSpec:
    _mapping(d, {"name", "urdf", "position_m", "yaw_rad", "mobile", "script", "script_period_s",
                 "script_amplitude", "color"}, where)
    urdf = _required(d, "urdf", where)
    if not isinstance(urdf, str):
        raise SceneError(f"{where}.urdf must be a file name, got {urdf!r}")
    path = urdf if os.path.isabs(urdf) else os.path.normpath(os.path.join(base_dir, urdf))
    if not os.path.isfile(path):
        raise SceneError(f"{where}.urdf: no such file '{path}'")
    a = ArmSpec(_name(d, where), path,
                tuple(numbers(_required(d, "position_m", where), 3, f"{where}.position_m")))
    a.yaw_rad = number(d.get("yaw_rad", 0.0), f"{where}.yaw_rad")
    mobile = d.get("mobile", False)
    if not isinstance(mobile, bool):
        raise SceneError(f"{where}.mobile must be true or false, got {mobile!r}")
    a.mobile = mobile
    a.script = d.get("script", "square" if mobile else "sine")
    if a.script not in SCRIPTS:
        raise SceneError(f"{where}.script must be one of {list(SCRIPTS)}, got {a.script!r}")
    a.script_period_s = positive(d.get("script_period_s", a.script_period_s),
                                  f"{where}.script_period_s")
    a.script_amplitude = number(d.get("script_amplitude", a.script_amplitude),
                                 f"{where}.script_amplitude")
    if not 0.0 <= a.script_amplitude <= 1.0:
        raise SceneError(f"{where}.script_amplitude must be in 0..1, got {a.script_amplitude}")
    a.color = color(d.get("color", a.color), f"{where}.color")
    return a


def _prox(d, where) -> ProxSpec:
    _mapping(d, {"name", "parent", "position_m", "rpy_rad", "min_range_m", "max_range_m"},
             where)
    p = ProxSpec(_name(d, where), str(_required(d, "parent", where)),
                 tuple(numbers(_required(d, "position_m", where), 3, f"{where}.position_m")),
                 tuple(numbers(d.get("rpy_rad", [0, 0, 0]), 3, f"{where}.rpy_rad")))
    p.min_range_m = positive(d.get("min_range_m", p.min_range_m), f"{where}.min_range_m")
    p.max_range_m = positive(d.get("max_range_m", p.max_range_m), f"{where}.max_range_m")
    if p.max_range_m <= p.min_range_m:
        raise SceneError(f"{where}: max_range_m must exceed min_range_m")
    return p


def _laser(d, where) -> LaserSpec:
    _mapping(d, {"name", "position_m", "yaw_rad", "topic", "count", "angle_min_rad",
                 "angle_increment_rad", "range_min_m", "range_max_m", "noise_sigma_m",
                 "noise_relative", "rate_hz"}, where)
    s = LaserSpec(_name(d, where),
                  tuple(numbers(_required(d, "position_m", where), 3, f"{where}.position_m")))
    s.yaw_rad = number(d.get("yaw_rad", 0.0), f"{where}.yaw_rad")
    s.topic = str(d.get("topic", s.topic))
    if not s.topic:
        raise SceneError(f"{where}.topic must not be empty")
    s.count = _count(d.get("count", s.count), f"{where}.count")
    s.angle_min_rad = number(d.get("angle_min_rad", s.angle_min_rad), f"{where}.angle_min_rad")
    for key in ("angle_increment_rad", "range_min_m", "range_max_m", "rate_hz"):
        setattr(s, key, positive(d.get(key, getattr(s, key)), f"{where}.{key}"))
    for key in ("noise_sigma_m", "noise_relative"):
        v = number(d.get(key, getattr(s, key)), f"{where}.{key}")
        if v < 0.0:
            raise SceneError(f"{where}.{key} must not be negative, got {v}")
        setattr(s, key, v)
    if s.range_max_m <= s.range_min_m:
        raise SceneError(f"{where}: range_max_m must exceed range_min_m")
    return s


def _resolution(v, where):
    if (not isinstance(v, (list, tuple)) or len(v) != 2
            or any(isinstance(x, bool) or not isinstance(x, int) or x < 1 or x > 4096
                   for x in v)):
        raise SceneError(f"{where} must be [width, height] in pixels (1..4096), got {v!r}")
    return tuple(v)


def _clipping(obj, d, where):
    obj.near_m = positive(d.get("near_m", obj.near_m), f"{where}.near_m")
    obj.far_m = positive(d.get("far_m", obj.far_m), f"{where}.far_m")
    if obj.far_m <= obj.near_m:
        raise SceneError(f"{where}: far_m must exceed near_m")


def _camera(d, where) -> CameraSpecEntry:
    _mapping(d, {"name", "matrix", "resolution", "angle_deg", "near_m", "far_m", "render",
                 "blob_topics"}, where)
    c = CameraSpecEntry(_name(d, where),
                        tuple(numbers(_required(d, "matrix", where), 12, f"{where}.matrix")))
    c.resolution = _resolution(d.get("resolution", list(c.resolution)), f"{where}.resolution")
    if "angle_deg" in d:
        angle = positive(d["angle_deg"], f"{where}.angle_deg")
        if angle >= 180.0:
            raise SceneError(f"{where}.angle_deg must be below 180, got {angle}")
        c.angle_rad = math.radians(angle)
    _clipping(c, d, where)
    c.render = d.get("render")
    topics = d.get("blob_topics", [])
    if topics and (not isinstance(topics, list) or len(topics) != 2
                   or not all(isinstance(t, str) and t for t in topics)):
        raise SceneError(f"{where}.blob_topics must be two topic names [x, y], got {topics!r}")
    c.blob_topics = tuple(topics)
    return c


def _kinect(d, where) -> KinectSpec:
    _mapping(d, {"name", "position_m", "rpy_rad", "resolution", "horizontal_fov_deg", "near_m",
                 "far_m"}, where)
    k = KinectSpec(name=str(d.get("name", "kinect")))
    k.position_m = tuple(numbers(_required(d, "position_m", where), 3, f"{where}.position_m"))
    k.rpy_rad = tuple(numbers(d.get("rpy_rad", [0, 0, 0]), 3, f"{where}.rpy_rad"))
    k.resolution = _resolution(d.get("resolution", list(k.resolution)), f"{where}.resolution")
    if "horizontal_fov_deg" in d:
        k.horizontal_fov_rad = math.radians(positive(d["horizontal_fov_deg"],
                                                      f"{where}.horizontal_fov_deg"))
    _clipping(k, d, where)
    return k

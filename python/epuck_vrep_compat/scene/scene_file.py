"""Scene files (YAML): the arena, its obstacles and the robots' start poses.

A malformed file raises :class:`SceneError` naming the offending key, so the node can exit
non-zero with a message that says what to fix. Lengths are metres, angles radians, colours RGB
in 0..1. See ``worlds/arena.yaml`` for a commented example.
"""
import math
import os
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

from epuck_vrep_compat.scene.cell_file import CellSpec, parse_cell
from epuck_vrep_compat.scene.floor_regions import FloorRegion, parse_floor_regions
from epuck_vrep_compat.scene.operator_file import check_on_floor
from epuck_vrep_compat.scene.validation import (  # noqa: F401  (SceneError, read_yaml: API)
    SceneError, as_list, color, number, numbers, only, positive, read_yaml)


@dataclass
class Obstacle:
    """A static box or cylinder of the arena."""
    name: str
    shape: str                                   # "box" | "cylinder"
    position_m: Tuple[float, float]
    yaw_rad: float = 0.0
    size_m: Tuple[float, float, float] = (0.1, 0.1, 0.05)   # box: full x, y, z extents
    radius_m: float = 0.03                                   # cylinder
    height_m: float = 0.05                                   # cylinder
    color: Tuple[float, float, float] = (0.8, 0.3, 0.2)

    def footprint_radius_m(self) -> float:
        if self.shape == "box":
            return 0.5 * math.hypot(self.size_m[0], self.size_m[1])
        return self.radius_m


@dataclass
class RobotStart:
    """Where an e-puck starts."""
    position_m: Tuple[float, float]
    yaw_rad: float = 0.0


@dataclass
class Arena:
    """The arena's floor and walls."""
    size_m: Tuple[float, float] = (1.0, 1.0)
    wall_height_m: float = 0.05
    wall_thickness_m: float = 0.01
    wall_color: Tuple[float, float, float] = (0.55, 0.55, 0.6)
    floor_color: Tuple[float, float, float] = (0.85, 0.85, 0.8)
    floor_name: str = "Floor"


@dataclass
class Scene:
    """A scene file, parsed: arena, obstacles, robot starts and the optional cell."""
    arena: Arena = field(default_factory=Arena)
    obstacles: List[Obstacle] = field(default_factory=list)
    robots: List[RobotStart] = field(default_factory=list)
    cell: Optional[CellSpec] = None          # arms, operator, sensors
    source: Optional[str] = None
    floor_regions: List[FloorRegion] = field(default_factory=list)   # ground sensors see them

    def refuse_unbuilt(self, extended_sections=()):
        """SceneError naming a section that only an extension builds (the e-pucks' ``robots``,
        the ``cell``) and that is not among ``extended_sections``: a simulation built without
        it would ignore part of the scene."""
        present = (("robots", "e-pucks'", bool(self.robots)),
                   ("cell", "cell's", self.cell is not None))
        for section, owner, used in present:
            if used and section not in extended_sections:
                raise SceneError(f"{self.source or 'scene'}: its '{section}' section needs the "
                                 f"{owner} extension, which Simulation(...) does not build; "
                                 "build the simulation with "
                                 "epuck_vrep_compat.builder.build.build_simulation")


def load_scene(path: str) -> Scene:
    data = read_yaml(path, "scene file")
    scene = parse_scene(data if data is not None else {}, where=path,
                        base_dir=os.path.dirname(os.path.abspath(path)))
    scene.source = path
    return scene


def parse_scene(data, where: str = "scene", base_dir: str = ".") -> Scene:
    """``base_dir``: where relative file names in the scene (URDFs) are looked up."""
    if not isinstance(data, dict):
        raise SceneError(f"{where}: the top level must be a mapping")
    only(data, {"arena", "obstacles", "robots", "cell", "floor_regions"}, where)
    arena = _arena(data.get("arena", {}), f"{where}: arena")
    obstacles = [_obstacle(o, i, f"{where}: obstacles[{i}]")
                 for i, o in enumerate(as_list(data.get("obstacles", []), f"{where}: obstacles"))]
    names = [o.name for o in obstacles]
    if len(set(names)) != len(names):
        raise SceneError(f"{where}: obstacles: names must be unique")
    robots = [_robot(r, f"{where}: robots[{i}]")
              for i, r in enumerate(as_list(data.get("robots", []), f"{where}: robots"))]
    cell = None
    if "cell" in data:
        cell = parse_cell(data["cell"], f"{where}: cell", base_dir)
        if cell.operator is not None:
            check_on_floor(cell.operator, arena.size_m)
    regions = parse_floor_regions(data.get("floor_regions", []), f"{where}: floor_regions")
    return Scene(arena, obstacles, robots, cell, floor_regions=regions)


def _arena(d, where) -> Arena:
    if not isinstance(d, dict):
        raise SceneError(f"{where} must be a mapping")
    only(d, {"size_m", "wall_height_m", "wall_thickness_m", "wall_color", "floor_color",
              "floor_name"}, where)
    a = Arena()
    if "size_m" in d:
        a.size_m = tuple(numbers(d["size_m"], 2, f"{where}.size_m", positive=True))
    a.wall_height_m = positive(d.get("wall_height_m", a.wall_height_m), f"{where}.wall_height_m")
    a.wall_thickness_m = positive(d.get("wall_thickness_m", a.wall_thickness_m),
                                   f"{where}.wall_thickness_m")
    a.wall_color = color(d.get("wall_color", a.wall_color), f"{where}.wall_color")
    a.floor_color = color(d.get("floor_color", a.floor_color), f"{where}.floor_color")
    a.floor_name = d.get("floor_name", a.floor_name)
    if not isinstance(a.floor_name, str) or not a.floor_name:
        raise SceneError(f"{where}.floor_name must be a non-empty string")
    return a


def _obstacle(d, index, where) -> Obstacle:
    if not isinstance(d, dict):
        raise SceneError(f"{where} must be a mapping")
    only(d, {"name", "shape", "position_m", "yaw_rad", "size_m", "radius_m", "height_m",
              "color"}, where)
    shape = d.get("shape")
    if shape not in ("box", "cylinder"):
        raise SceneError(f"{where}.shape must be 'box' or 'cylinder', got {shape!r}")
    if "position_m" not in d:
        raise SceneError(f"{where}.position_m is required")
    o = Obstacle(name=str(d.get("name", f"obstacle{index}")), shape=shape,
                 position_m=tuple(numbers(d["position_m"], 2, f"{where}.position_m")))
    o.yaw_rad = number(d.get("yaw_rad", 0.0), f"{where}.yaw_rad")
    if "size_m" in d:
        o.size_m = tuple(numbers(d["size_m"], 3, f"{where}.size_m", positive=True))
    o.radius_m = positive(d.get("radius_m", o.radius_m), f"{where}.radius_m")
    o.height_m = positive(d.get("height_m", o.height_m), f"{where}.height_m")
    o.color = color(d.get("color", o.color), f"{where}.color")
    return o


def _robot(d, where) -> RobotStart:
    if not isinstance(d, dict):
        raise SceneError(f"{where} must be a mapping")
    only(d, {"position_m", "yaw_rad"}, where)
    if "position_m" not in d:
        raise SceneError(f"{where}.position_m is required")
    return RobotStart(tuple(numbers(d["position_m"], 2, f"{where}.position_m")),
                      number(d.get("yaw_rad", 0.0), f"{where}.yaw_rad"))

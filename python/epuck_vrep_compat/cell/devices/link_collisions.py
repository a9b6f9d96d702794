"""The collision primitives (box, cylinder, sphere) of URDF links: read from the URDF, and
mirrored into the core's collision world so the ray-cast sensors see the robots.
"""
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from typing import Dict, List

import numpy as np

from epuck_vrep_compat._core import GROUP_ROBOT
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import (
    IDENTITY_QUAT, quat_from_rpy, quat_mul, quat_rotate)


@dataclass
class Collision:
    """One collision primitive of a link, in the link's frame."""
    shape: str                   # box | cylinder | sphere
    size: tuple                  # box: full extents; cylinder: (radius, length); sphere: (r,)
    position: np.ndarray
    quat: np.ndarray


def _origin(element):
    o = element.find("origin")
    if o is None:
        return np.zeros(3), IDENTITY_QUAT.copy()
    xyz = np.array([float(v) for v in o.get("xyz", "0 0 0").split()])
    rpy = [float(v) for v in o.get("rpy", "0 0 0").split()]
    return xyz, quat_from_rpy(*rpy)


def parse_collisions(path: str) -> Dict[str, List[Collision]]:
    """Each link's collision primitives (the joints come from :func:`load_urdf_chain`)."""
    collisions = {}
    for link in ET.parse(path).getroot().findall("link"):
        shapes = []
        for c in link.findall("collision"):
            geometry = c.find("geometry")
            position, quat = _origin(c)
            box, cyl, sph = (geometry.find(k) for k in ("box", "cylinder", "sphere"))
            if box is not None:
                shapes.append(Collision("box", tuple(float(v) for v in box.get("size").split()),
                                        position, quat))
            elif cyl is not None:
                shapes.append(Collision("cylinder", (float(cyl.get("radius")),
                                                     float(cyl.get("length"))), position, quat))
            elif sph is not None:
                shapes.append(Collision("sphere", (float(sph.get("radius")),), position, quat))
            else:
                raise ValueError(f"{path}: link '{link.get('name')}' has a collision geometry "
                                 "other than box, cylinder or sphere")
        collisions[link.get("name")] = shapes
    return collisions


def world_poses(link_position, link_quat, rows, offsets_position, offsets_quat):
    """Vectorised link_world[rows] * offset."""
    q = link_quat[rows]
    return link_position[rows] + quat_rotate(q, offsets_position), quat_mul(q, offsets_quat)


def add_primitive(world, handle, part: Collision, color, group):
    """A collision primitive into the core's collision world (posed later)."""
    if part.shape == "box":
        world.add_box(handle, 0.5 * np.asarray(part.size), np.zeros(3), IDENTITY_QUAT,
                      color, group)
    elif part.shape == "cylinder":
        world.add_cylinder(handle, part.size[0], part.size[1], np.zeros(3), IDENTITY_QUAT,
                           color, group)
    else:
        world.add_sphere(handle, part.size[0], np.zeros(3), IDENTITY_QUAT, color, group)


def _collision_handle(registry, link_obj, k, robot):
    """The object a link's k-th primitive hangs on: the link itself for its first, else a new
    ``<link>_collision<k>`` shape under it."""
    if k == 0 and "collision" not in link_obj.properties:
        link_obj.properties["collision"] = True
        return link_obj.handle
    name = f"{link_obj.name}_collision{k}"
    while registry.handle_of(name) >= 0:
        k += 1
        name = f"{link_obj.name}_collision{k}"
    return registry.add(name, vc.OBJECT_SHAPE, link_obj.handle, robot=robot, part=name).handle


class LinkCollisions:
    """Every link primitive of the cell's arms in the collision world, with the stacked arrays
    that pose them all from the links' poses in one batched call."""

    def __init__(self, arms, registry, world):
        self._entries = []      # (arm, handle, row in the arm's links, primitive)
        for arm in arms:
            self.add(arm, registry, world)
        self.index(arms)

    def add(self, arm, registry, world):
        """An arm's primitives into the world (index again after)."""
        for k, (row, part) in enumerate(arm.collision_parts()):
            link_obj = arm.objects[arm.link_names[row]]
            handle = _collision_handle(registry, link_obj, k, arm.spec.name)
            add_primitive(world, handle, part, arm.spec.color, GROUP_ROBOT)
            self._entries.append((arm, handle, row, part))

    def index(self, arms):
        """The stacked arrays, from the arms there are (in the order of their links' rows)."""
        first_row, row0 = {}, 0
        for arm in arms:
            first_row[id(arm)] = row0
            row0 += len(arm.link_names)
        kept = [c for c in self._entries if id(c[0]) in first_row]
        self._entries = kept
        self.handles = np.asarray([h for _, h, _, _ in kept], dtype=np.int32)
        self.rows = np.asarray([first_row[id(a)] + r for a, _, r, _ in kept], dtype=np.intp)
        self.offset_p = np.asarray([p.position for *_, p in kept], dtype=float).reshape(-1, 3)
        self.offset_q = np.asarray([p.quat for *_, p in kept], dtype=float).reshape(-1, 4)

    def world_poses(self, positions, quats):
        """World poses of the primitives, given every link's (stacked over the arms)."""
        return world_poses(positions, quats, self.rows, self.offset_p, self.offset_q)

"""The cell's ray proximity sensors on robot links: registered as V-REP proximity sensors and
cast all at once by the core after each step (:class:`RayProximityBank`); each sensor's
component (:class:`RayProximity`) answers from the bank's last reading.
"""
import numpy as np

from epuck_vrep_compat import _core
from epuck_vrep_compat._core import GROUP_ALL
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.cell.devices.link_collisions import world_poses
from epuck_vrep_compat.geometry.transforms import IDENTITY_QUAT, quat_from_rpy


class RayProximity:
    """A ray-type proximity sensor (V-REP: detection along its z axis), read from the bank's
    last step."""

    subtype = vc.PROXSENSOR_RAY

    def __init__(self, bank, index: int):
        self._bank = bank
        self._index = index

    def renumber(self, index: int):
        """The sensor's row in the bank's arrays, after sensors before it were removed."""
        self._index = index

    def read(self):
        """(detection state 0/1, point in the sensor frame (3), object handle or -1, normal)."""
        b = self._bank
        i = self._index
        if not b.state[i]:
            return 0, np.zeros(3), -1, np.zeros(3)
        return 1, b.point[i].copy(), int(b.hit[i]), b.normal[i].copy()


class RayProximityBank:
    """Every ray proximity sensor of the cell, with the stacked arrays that pose and cast them
    in one batched call: ``handles`` (their objects), ``rows`` (their links' rows among every
    link), and the last reading ``state``, ``distance``, ``point``, ``hit``, ``normal``."""

    def __init__(self, specs, registry, link_row):
        """``specs``: the ProxSpecs; ``link_row(link name)``: (its arm, its row among every
        link), ValueError for a name that is not a link."""
        self._link_row = link_row
        self._entries = []                          # (spec, scene object, component)
        for p in specs:
            arm, _ = link_row(p.parent)
            quat = quat_from_rpy(*p.rpy_rad)
            obj = registry.add(p.name, vc.OBJECT_PROXIMITY_SENSOR, arm.objects[p.parent].handle,
                               p.position_m, quat, robot=arm.spec.name, part=p.name)
            component = RayProximity(self, len(self._entries))
            obj.properties["proximity"] = component
            obj.properties["range_m"] = (p.min_range_m, p.max_range_m)
            self._entries.append((p, obj, component))
        self.index(registry)

    def index(self, registry):
        """The core's ray array and the per-sensor arrays, from the sensors still in
        ``registry`` (on links of the arms there are)."""
        self._entries = [entry for entry in self._entries if entry[1].handle in registry]
        specs = [p for p, _, _ in self._entries]
        n = len(specs)
        self.rows = np.zeros(n, dtype=np.intp)
        self.offset_p = np.zeros((n, 3))
        self.offset_q = np.tile(IDENTITY_QUAT, (n, 1))
        for i, (p, _, component) in enumerate(self._entries):
            self.rows[i] = self._link_row(p.parent)[1]
            self.offset_p[i] = p.position_m
            self.offset_q[i] = quat_from_rpy(*p.rpy_rad)
            component.renumber(i)
        self.handles = [obj.handle for _, obj, _ in self._entries]
        self.sensors = _core.RayProximityArray(
            np.array([p.min_range_m for p in specs]), np.array([p.max_range_m for p in specs]))
        self.state = np.zeros(n, dtype=np.int32)
        self.distance = np.full(n, np.inf)
        self.point = np.zeros((n, 3))
        self.hit = np.full(n, -1, dtype=np.int32)
        self.normal = np.zeros((n, 3))

    def sense(self, world, positions, quats):
        """Cast every ray, given every link's pose (stacked over the arms)."""
        if len(self.rows):
            sp, sq = world_poses(positions, quats, self.rows, self.offset_p, self.offset_q)
            (self.state, self.distance, self.point, self.hit,
             self.normal) = self.sensors.read(world, sp, sq, -1, GROUP_ALL)

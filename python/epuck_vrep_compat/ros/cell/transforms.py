"""The cell's TF: ``world -> <object>`` every step for every link of the cell's robots, the
operator, the scanner, the cameras and the Kinect's sensors (frames are V-REP object names)."""
import numpy as np

from epuck_vrep_compat.ros.common.names import WORLD_FRAME
from epuck_vrep_compat.ros.transport.wire import TransformBatchWire


class CellTransforms:
    """The cell's frames, laid out once per change of the cell's objects."""

    def __init__(self, sim):
        self._sim = sim
        self.index()

    def index(self):
        """Lay out the frames of the objects there are now."""
        self._objects = self._frames()
        self._wire = TransformBatchWire([(WORLD_FRAME, name) for name, _ in self._objects])

    def _frames(self):
        """[(frame, source)]: source is a row of the stacked link poses, or a handle."""
        cell = self._sim.cell
        out = []
        row = 0
        for arm in cell.arms:
            for link in arm.link_names:
                out.append((arm.objects[link].name, ("row", row)))
                row += 1
        extra = []
        if cell.operator is not None:
            extra.append(cell.operator_handles[0])
        if cell.laser is not None:
            extra.append(cell.laser_handle)
        extra += [c.handle for c in cell.cameras]
        extra += [v.handle for v in (cell.kinect_depth, cell.kinect_rgb) if v is not None]
        out += [(self._sim.registry.get(h).name, ("handle", h)) for h in extra]
        return out

    def message(self, secs, nsecs):
        """This step's transforms, pre-serialised."""
        positions, quats = self._sim.cell.link_poses()
        t = np.empty((len(self._objects), 3))
        r = np.empty((len(self._objects), 4))
        n = len(positions)
        t[:n], r[:n] = positions, quats
        for i, (_, (kind, h)) in enumerate(self._objects[n:], start=n):
            t[i], r[i] = self._sim.registry.world_pose(h)
        return self._wire.pack(secs, nsecs, t, r)

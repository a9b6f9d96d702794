"""The cell's TF (frames are V-REP object names): ``world -> <object>`` every step on ``/tf``
for every link of the cell's robots and the operator; the sensor mounts that stay where the
scene put them (the scanner, the cameras, the Kinect's sensors) on the latched ``/tf_static``,
sent again only when one of them was moved (a ``/vrep`` pose service) or removed."""
import numpy as np

from epuck_vrep_compat.compat.frames import WORLD_FRAME
from epuck_vrep_compat.ros.transport.static_tf import static_transform
from epuck_vrep_compat.ros.transport.wire import TransformBatchWire

STATIC_PART = "cell"


class CellTransforms:
    """The cell's frames, laid out once per change of the cell's objects; ``static_tf``: the
    node's :class:`~epuck_vrep_compat.ros.transport.static_tf.StaticTransforms`."""

    def __init__(self, sim, static_tf):
        self._sim = sim
        self._static_tf = static_tf
        self.index()

    def index(self):
        """Lay out the frames of the objects there are now."""
        self._objects = self._moving_frames()
        self._wire = TransformBatchWire([(WORLD_FRAME, name) for name, _ in self._objects])
        self._mounts = self._mount_handles()
        self._mount_poses = None
        self.update_static(0, 0)

    def _moving_frames(self):
        """[(frame, source)]: source is a row of the stacked link poses, or a handle."""
        cell = self._sim.cell
        out = []
        row = 0
        for arm in cell.arms:
            for link in arm.link_names:
                out.append((arm.objects[link].name, ("row", row)))
                row += 1
        if cell.operator is not None:
            handle = cell.operator_handles[0]
            out.append((self._sim.registry.get(handle).name, ("handle", handle)))
        return out

    def _mount_handles(self):
        cell = self._sim.cell
        mounts = [cell.laser_handle] if cell.laser is not None else []
        mounts += [c.handle for c in cell.cameras]
        mounts += [v.handle for v in (cell.kinect_depth, cell.kinect_rgb) if v is not None]
        return mounts

    def update_static(self, secs, nsecs):
        """Send the mounts' frames on ``/tf_static`` when they changed since the last time."""
        registry = self._sim.registry
        poses = [registry.world_pose(h) for h in self._mounts]
        flat = np.array([np.concatenate(p) for p in poses]).reshape(-1, 7)
        if self._mount_poses is not None and np.array_equal(flat, self._mount_poses):
            return
        self._mount_poses = flat
        self._static_tf.set(STATIC_PART, [
            static_transform(WORLD_FRAME, registry.get(h).name, p, q, secs, nsecs)
            for h, (p, q) in zip(self._mounts, poses)])

    def message(self, secs, nsecs):
        """This step's moving transforms, pre-serialised."""
        positions, quats = self._sim.cell.link_poses()
        t = np.empty((len(self._objects), 3))
        r = np.empty((len(self._objects), 4))
        n = len(positions)
        t[:n], r[:n] = positions, quats
        for i, (_, (kind, h)) in enumerate(self._objects[n:], start=n):
            t[i], r[i] = self._sim.registry.world_pose(h)
        return self._wire.pack(secs, nsecs, t, r)

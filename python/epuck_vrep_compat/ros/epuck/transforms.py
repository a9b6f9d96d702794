"""The TF tree of every robot: what moves in one ``/tf`` message per step, the rest latched.

Per robot: ``odom -> <robot>/base_link`` (ground truth in the ``vrep`` profile, wheel odometry in
``epuck_driver``), then under base_link: ``base_prox0..7`` (V-REP's ``dummy_proxSensor``
objects), ``left_wheel``/``right_wheel`` (turning with the wheels), ``body_top`` (``ePuck_ring``),
``camera_optical`` and, for the driver profile, ``base_laser``. Fixed offsets are read once from
the scene registry, so the frames and the simulated parts cannot disagree.

Only ``base_link`` and the wheels move: they go on ``/tf`` every step (V-REP's script sent all
frames there). The frames fixed to base_link go once on the latched ``/tf_static``, as
``robot_state_publisher`` sends a robot's fixed joints, and again whenever robots come or go.
"""
import numpy as np

from epuck_vrep_compat.compat import epuck_names
from epuck_vrep_compat.compat.frames import ODOM_FRAME
from epuck_vrep_compat.geometry.transforms import quat_from_axis_angle, quat_from_yaw, quat_mul
from epuck_vrep_compat.ros.epuck import profiles
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.transport.static_tf import static_transform
from epuck_vrep_compat.ros.transport.wire import TransformBatchWire

_OPTICAL_FROM_VISION = quat_from_axis_angle((0, 0, 1), np.pi)


def robot_child_frames(profile, sim, index):
    """[(child frame, translation, quaternion or None for wheels)] under base_link."""
    parts = sim.epucks.robots[index].parts
    out = []
    for i in range(epuck_names.PROXIMITY_COUNT):
        obj = parts[f"dummy_proxSensor{i}"]
        out.append((epuck_names.PROX_FRAME_FORMAT.format(i=i), obj.local_position, obj.local_quat))
    for side, frame in zip(("left", "right"), epuck_names.WHEEL_FRAMES):
        joint = parts[f"{side}Joint"]
        out.append((frame, joint.local_position, None))
    ring = parts["ring"]
    out.append((epuck_names.BODY_TOP_FRAME, ring.local_position, ring.local_quat))
    camera = parts["camera"]
    out.append((epuck_names.CAMERA_FRAME, camera.local_position,
                quat_mul(camera.local_quat, _OPTICAL_FROM_VISION)))
    if profile.publishes_scan:
        out.append((epuck_names.LASER_FRAME, np.array([0.0, 0.0, 0.034]), np.array([0, 0, 0, 1.0])))
    if "dist_sens" in profile.extras:
        out.append((epuck_names.DIST_SENS_FRAME, np.array(profiles.DIST_SENS_MOUNT_M),
                    quat_from_axis_angle((0, 1, 0), profiles.DIST_SENS_PITCH_RAD)))
    return out


class TfFace(Face):
    """The e-pucks' TF tree: the moving frames in one ``/tf`` message per step, through the
    shared batch; the fixed ones on ``static_tf`` (the node's
    :class:`~epuck_vrep_compat.ros.transport.static_tf.StaticTransforms`)."""

    STATIC_PART = "epucks"

    def __init__(self, profile, sim, static_tf):
        self._profile = profile
        self._sim = sim
        self._static_tf = static_tf
        self.sync()

    def sync(self):
        """Lay out the frames of the robots there are now (after robots came or went)."""
        profile, sim = self._profile, self._sim
        frames, translations, rotations = [], [], []
        base_rows, wheel_rows, static = [], [], []
        stamp = divmod(int(round(sim.time_s * 1e9)), 1_000_000_000)
        for i, robot in enumerate(sim.epucks.robot_names):
            base = profile.frame(robot, epuck_names.BASE_FRAME)
            base_rows.append(len(frames))
            frames.append((ODOM_FRAME, base))
            translations.append(np.zeros(3))
            rotations.append(np.array([0, 0, 0, 1.0]))
            for child, translation, quat in robot_child_frames(profile, sim, i):
                if quat is not None:
                    static.append(static_transform(base, profile.frame(robot, child),
                                                   translation, quat, *stamp))
                    continue
                wheel_rows.append(len(frames))
                frames.append((base, profile.frame(robot, child)))
                translations.append(np.asarray(translation, dtype=float))
                rotations.append(np.array([0, 0, 0, 1.0]))
        self._static_tf.set(self.STATIC_PART, static)
        self._wire = TransformBatchWire(frames)
        self._translations = np.array(translations).reshape(-1, 3)
        self._rotations = np.array(rotations).reshape(-1, 4)
        self._base_rows = np.array(base_rows, dtype=np.intp)
        self._wheel_rows = np.array(wheel_rows, dtype=np.intp).reshape(-1, 2)
        self.frames = frames

    def publish(self, step: Step):
        """This step's transforms on ``/tf``, when someone listens."""
        if step.batch.wanted(step.tf) and self.frames:
            step.add_tf("epucks", self._wire.frame(step.secs, step.nsecs, *self._moving()))

    def message(self, secs: int, nsecs: int):
        """This step's moving transforms of every robot; None while there is no robot."""
        if not self.frames:
            return None
        return self._wire.pack(secs, nsecs, *self._moving())

    def _moving(self):
        """(translations (M, 3), rotations (M, 4)) of this step's moving frames."""
        swarm = self._sim.epucks.swarm
        if self._profile.odom_tf_from_odometry:
            planar = swarm.odometry[:, :3]
        else:
            planar = swarm.poses
        t = self._translations
        r = self._rotations
        t[self._base_rows, 0] = planar[:, 0]
        t[self._base_rows, 1] = planar[:, 1]
        r[self._base_rows] = quat_from_yaw(planar[:, 2])
        r[self._wheel_rows] = quat_from_axis_angle((0, 1, 0), swarm.wheel_angles)
        return t, r

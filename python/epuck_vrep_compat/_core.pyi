"""Type stub of epuck_vrep_compat._core, the C++ core (see include/epuck_vrep_compat/)."""
from typing import List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

ArrayLike = Union[npt.ArrayLike, Sequence[float]]
FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int32]
BoolArray = npt.NDArray[np.bool_]

GROUP_STATIC: int  # 1: walls, fixed obstacles
GROUP_ROBOT: int  # 2: robot bodies
GROUP_FLOOR: int  # 4: the ground; robots never touch it, IR cones never see it
GROUP_DYNAMIC: int  # 8: movable objects (fixed for contact resolution)
GROUP_ALL: int  # 15: every group, as a ray or camera mask
WORLD_LIMIT_M: float  # 1e6: every position the core takes lies within +-WORLD_LIMIT_M [m]

class Rng:
    """Seeded xoshiro256** generator (splitmix64 seeding), reproducible bit for bit."""

    def __init__(self, seed: int) -> None: ...
    def uniform(self) -> float:
        """A uniform draw in (0, 1]."""
    def normal(self) -> float:
        """sqrt(-2 ln U1) cos(2 pi U2): one standard normal per two uniforms."""
    def state_digest(self) -> int:
        """A 64-bit digest of the generator state."""

def apply_range_noise(
    clean: ArrayLike,
    min_range_m: float,
    max_range_m: float,
    probability: float,
    mean_m: float,
    stddev_m: float,
    seed: int,
) -> Tuple[FloatArray, npt.NDArray[np.bool_]]:
    """V-REP e-puck IR noise on readings (M,); returns (noisy (M,), applied (M,) bool).

    Raises ValueError for probability outside [0, 1], negative stddev_m, non-finite values.
    """

class CollisionWorld:
    """Bullet collision world of boxes, cylinders and spheres keyed by int handles >= 0.

    Unknown handles raise KeyError; bad arguments (a used handle, non-finite or wrongly
    shaped arrays, sizes <= 0, colours outside [0, 1], a group that is not one GROUP_ bit)
    raise ValueError.
    """

    def __init__(self) -> None: ...
    def add_box(
        self,
        handle: int,
        half_extents: ArrayLike,
        position: ArrayLike,
        quaternion: ArrayLike,
        rgb: ArrayLike,
        group: int = ...,
    ) -> None:
        """Adds a box; quaternion is (x, y, z, w); group defaults to GROUP_STATIC."""
    def add_cylinder(
        self,
        handle: int,
        radius: float,
        height: float,
        position: ArrayLike,
        quaternion: ArrayLike,
        rgb: ArrayLike,
        group: int = ...,
    ) -> None:
        """Adds a cylinder with its axis along local z, centred at position."""
    def add_sphere(
        self,
        handle: int,
        radius: float,
        position: ArrayLike,
        quaternion: ArrayLike,
        rgb: ArrayLike,
        group: int = ...,
    ) -> None:
        """Adds a sphere."""
    def set_pose(self, handle: int, position: ArrayLike, quaternion: ArrayLike) -> None: ...
    def set_poses(
        self, handles: ArrayLike, positions: ArrayLike, quaternions: ArrayLike
    ) -> None:
        """Moves M objects: handles (M,) int, positions (M, 3), quaternions (M, 4) x, y, z, w.

        All or none: KeyError for an unknown handle, ValueError for bad shapes or values
        (naming the argument or "poses[i]"); nothing moves then.
        """
    def get_pose(self, handle: int) -> Tuple[FloatArray, FloatArray]:
        """Returns (position (3,), quaternion x, y, z, w (4,))."""
    def remove(self, handle: int) -> None: ...
    def has(self, handle: int) -> bool: ...
    def handles(self) -> List[int]:
        """Every handle, ascending."""
    def set_color(self, handle: int, rgb: ArrayLike) -> None: ...
    def set_background(self, rgb: ArrayLike) -> None: ...
    def ray_cast(
        self,
        origins: ArrayLike,
        directions: ArrayLike,
        max_distance_m: float,
        ignore_handle: int = -1,
        mask: int = ...,
    ) -> Tuple[FloatArray, IntArray, FloatArray]:
        """Rays (M, 3); returns (distance (M,) +inf for none, handle (M,) -1 for none,
        world normal (M, 3)). Releases the GIL."""
    def render(
        self,
        position: ArrayLike,
        quaternion: ArrayLike,
        width: int,
        height: int,
        vertical_fov_rad: float,
        near_m: float,
        far_m: float,
        ignore_handle: int = -1,
        mask: int = ...,
        rgb: bool = True,
        depth: bool = True,
        depth_out: Optional[npt.NDArray[np.float32]] = None,
    ) -> Tuple[npt.NDArray[np.uint8], npt.NDArray[np.float32]]:
        """Camera x forward, y left, z up; returns (rgb (H, W, 3), depth (H, W)), row 0 at
        the top; depth along the optical axis in [near_m, far_m], far_m for no hit (None for
        an image not asked for); ``depth_out``: a float32 (H, W) array to render the depth
        into."""
    def closest_points(
        self, handle_a: int, handle_b: int
    ) -> Tuple[float, FloatArray, FloatArray]:
        """(distance m, < 0 overlapping; point on A (3,); point on B (3,)), world frame."""
    def minimum_distances(
        self, handles_a: List[int], handles_b: List[int], group_of_b: List[int], groups: int
    ) -> Tuple[FloatArray, FloatArray, FloatArray, IntArray, IntArray]:
        """Per group of B objects, the closest pair with any A object: (distance (G,), +inf
        for an empty group; point on A (G, 3); point on B (G, 3); A index (G,); B handle (G,))."""
    def minimum_distances_to(
        self,
        shapes_a: List["ConvexShape"],
        positions_a: ArrayLike,
        quaternions_a: ArrayLike,
        handles_b: List[int],
        group_of_b: List[int],
        groups: int,
    ) -> Tuple[FloatArray, FloatArray, FloatArray, IntArray, IntArray]:
        """minimum_distances with the A objects given by value, at poses (M, 3), (M, 4)."""

class ConvexShape:
    """A convex shape by value (box, cylinder, sphere, capsule; axes along local z)."""

    kind: str
    @staticmethod
    def box(half_extents: ArrayLike) -> "ConvexShape": ...
    @staticmethod
    def cylinder(radius: float, height: float) -> "ConvexShape": ...
    @staticmethod
    def sphere(radius: float) -> "ConvexShape": ...
    @staticmethod
    def capsule(radius: float, segment: float) -> "ConvexShape": ...

def closest_points(
    shape_a: ConvexShape,
    position_a: ArrayLike,
    quaternion_a: ArrayLike,
    shape_b: ConvexShape,
    position_b: ArrayLike,
    quaternion_b: ArrayLike,
) -> Tuple[float, FloatArray, FloatArray]:
    """Closest points of two shapes at poses: (distance m, point on A, point on B)."""

class ConeSensor:
    """Mount (body frame: x forward, y left, z up from the ground) and cone of an IR sensor."""

    yaw_rad: float
    pitch_rad: float  # positive tilts the axis down
    half_angle_rad: float
    min_range_m: float
    max_range_m: float
    rings: int
    azimuths: int  # even
    def __init__(
        self,
        position: ArrayLike = ...,
        yaw_rad: float = 0.0,
        pitch_rad: float = 0.0,
        half_angle_rad: float = 0.2617993878,
        min_range_m: float = 0.0015,
        max_range_m: float = 0.05,
        rings: int = 2,
        azimuths: int = 16,
    ) -> None: ...
    @property
    def position(self) -> Tuple[float, float, float]: ...
    @position.setter
    def position(self, value: ArrayLike) -> None: ...

class EpuckModel:
    """e-puck geometry and limits with V-REP's defaults."""

    wheel_radius_m: float
    wheel_separation_m: float
    body_radius_m: float
    body_height_m: float
    max_wheel_speed_rad_s: float
    sensors: List[ConeSensor]  # a copy on read: edit, then assign the whole list back
    gravity_m_s2: float
    def __init__(
        self,
        wheel_radius_m: float = 0.02,
        wheel_separation_m: float = 0.053,
        body_radius_m: float = 0.037,
        body_height_m: float = 0.045,
        max_wheel_speed_rad_s: float = 6.283185307,
        sensors: List[ConeSensor] = ...,
        gravity_m_s2: float = 9.81,
    ) -> None: ...

class EpuckSwarm:
    """N e-pucks stepped together; K = len(model.sensors) (8 by default).

    Rows are robot indices. Wheel columns are (left, right).
    """

    def __init__(self, world: CollisionWorld, model: EpuckModel, seed: int) -> None: ...
    def add_robot(self, handle: int, x: float, y: float, yaw: float) -> int: ...
    def remove_robot(self, index: int) -> None:
        """Removes a robot and its body; later rows move up, keeping state and noise streams."""
    @property
    def size(self) -> int: ...
    @property
    def sensor_count(self) -> int: ...
    def set_ir_noise(
        self, probability: ArrayLike, mean_m: ArrayLike, stddev_m: ArrayLike
    ) -> None:
        """Each (N, K)."""
    def set_imu_noise(self, accel_stddev: ArrayLike, gyro_stddev: ArrayLike) -> None:
        """Each (N, 3)."""
    def set_imu_bias(self, accel_bias: ArrayLike, gyro_bias: ArrayLike) -> None:
        """Each (N, 3): m/s^2 and rad/s, added to every reading."""
    def set_slip_noise(self, stddev: ArrayLike) -> None:
        """(N,)."""
    def reseed(self, seed: int) -> None: ...
    def reset(self, seed: int) -> None:
        """Starts over where the robots stand: frame 0, noise streams from seed, odometry at
        the pose; velocities, wheels and readings as when the robots were added."""
    def step(self, dt_s: float, wheel_cmd: ArrayLike) -> None:
        """wheel_cmd (N, 2) rad/s; non-finite commands stop that robot. Releases the GIL."""
    def set_pose(self, index: int, x: float, y: float, yaw: float) -> None: ...
    def set_odometry(self, index: int, x: float, y: float, yaw: float) -> None: ...
    def sensor_model(self, i: int) -> ConeSensor: ...
    @property
    def poses(self) -> FloatArray:
        """(N, 3) x, y, yaw."""
    @property
    def velocities(self) -> FloatArray:
        """(N, 3) vx, vy (world), yaw rate."""
    @property
    def wheel_speeds(self) -> FloatArray:
        """(N, 2) rad/s after clamp and slip."""
    @property
    def wheel_angles(self) -> FloatArray:
        """(N, 2) rad, cumulative."""
    @property
    def odometry(self) -> FloatArray:
        """(N, 5) x, y, yaw, v, w."""
    @property
    def ranges_clean(self) -> FloatArray:
        """(N, K) m; max_range_m where nothing is detected."""
    @property
    def ranges(self) -> FloatArray:
        """(N, K) m, with noise."""
    @property
    def detected_handles(self) -> IntArray:
        """(N, K), -1 for none."""
    @property
    def detected_points(self) -> FloatArray:
        """(N, K, 3) sensor frame, zeros for none."""
    @property
    def detected_normals(self) -> FloatArray:
        """(N, K, 3) sensor frame, zeros for none."""
    @property
    def accel(self) -> FloatArray:
        """(N, 3) body-frame specific force, m/s^2 (+g on z at rest)."""
    @property
    def gyro(self) -> FloatArray:
        """(N, 3) rad/s."""
    @property
    def in_contact(self) -> BoolArray:
        """(N,) touched an obstacle or another robot during the last step."""
    @property
    def frame(self) -> int: ...
    @property
    def handles(self) -> IntArray: ...
    @property
    def stream_ids(self) -> List[int]:
        """Noise stream id of each robot: how many robots were added before it."""

class RayProximityArray:
    """M single-ray proximity sensors (V-REP "ray type"): sensor i looks along its local +z
    axis from its origin and detects the first surface at min_range_m[i] <= d <= max_range_m[i].
    A surface nearer than min_range_m blinds the sensor (it is not seen through)."""

    def __init__(
        self,
        min_range_m: ArrayLike,
        max_range_m: ArrayLike,
        noise_stddev_m: float = 0.0,
        seed: int = 0,
    ) -> None:
        """Ranges (M,) each, m. Gaussian noise on detected distances (clamped to the range),
        one draw per sensor per read from its own Rng(seed); 0 disables it."""
    def read(
        self,
        world: CollisionWorld,
        positions: ArrayLike,
        quaternions: ArrayLike,
        ignore_handles: Union[int, ArrayLike] = -1,
        mask: int = ...,
    ) -> Tuple[IntArray, FloatArray, FloatArray, IntArray, FloatArray]:
        """Sensor poses (M, 3) and (M, 4) x, y, z, w in the world; ignore_handles (M,) or one int.

        Returns, in V-REP's order: (detected (M,) int32 0/1, distance (M,) m (+inf: nothing
        within max_range_m, -inf: first surface nearer than min_range_m), point (M, 3) in the
        sensor frame (= (0, 0, distance)), handle (M,) int32 (-1: none), normal (M, 3) in the
        sensor frame). point, normal are zero where not detected. Releases the GIL.
        """
    def reseed(self, seed: int) -> None: ...
    @property
    def size(self) -> int: ...
    @property
    def min_range_m(self) -> FloatArray: ...
    @property
    def max_range_m(self) -> FloatArray: ...
    @property
    def noise_stddev_m(self) -> float: ...

class LaserScanner:
    """Planar laser scanner; the defaults are the Hokuyo URG-04LX-UG01 (682 beams of 2 pi/1024
    from -119.53 deg, 0.02-5.6 m). Beam k lies in the scanner's x-y plane at angle_min_rad +
    k angle_increment_rad from +x towards +y (sensor_msgs/LaserScan). Noise SD
    max(sigma_min_m, sigma_rel r) (models.md: 0.01 and 0.01; both 0 by default: off)."""

    def __init__(
        self,
        angle_min_rad: float = ...,
        angle_increment_rad: float = ...,
        count: int = 682,
        range_min_m: float = 0.02,
        range_max_m: float = 5.6,
        sigma_min_m: float = 0.0,
        sigma_rel: float = 0.0,
        seed: int = 0,
    ) -> None: ...
    def scan(
        self,
        world: CollisionWorld,
        position: ArrayLike,
        quaternion: ArrayLike,
        ignore_handle: int = -1,
        mask: int = ...,
    ) -> npt.NDArray[np.float32]:
        """Ranges (count,) m from the scanner frame at position (3,), quaternion (4,) x, y, z, w.

        REP 117: +inf for no return within range_max_m, -inf for one nearer than range_min_m.
        One noise draw per beam per scan, in beam order: same seed and scene, same scans.
        Releases the GIL.
        """
    def reseed(self, seed: int) -> None: ...
    @property
    def angle_min_rad(self) -> float: ...
    @property
    def angle_increment_rad(self) -> float: ...
    @property
    def count(self) -> int: ...
    @property
    def range_min_m(self) -> float: ...
    @property
    def range_max_m(self) -> float: ...
    @property
    def sigma_min_m(self) -> float: ...
    @property
    def sigma_rel(self) -> float: ...

class DepthNoise:
    """Kinect v1 axial depth noise sigma_z(z) = a_m + b_per_m (z - c_m)^2 (Nguyen et al. 2012),
    then, if inverse_depth_step_per_m = k > 0, 1/z rounded to multiples of k (disparity
    quantisation; the Kinect's is about 2.87e-3 per m)."""

    def __init__(
        self,
        a_m: float = 0.0012,
        b_per_m: float = 0.0019,
        c_m: float = 0.4,
        inverse_depth_step_per_m: float = 0.0,
        seed: int = 0,
    ) -> None: ...
    def apply(
        self, depth: npt.ArrayLike, near_m: float, far_m: float,
        out: Optional[npt.NDArray[np.float32]] = None,
    ) -> npt.NDArray[np.float32]:
        """A noisy copy of depth (H, W) m: values >= far_m (no return) stay far_m, the others
        are clamped to [near_m, far_m]. One draw per pixel, row-major. Releases the GIL.
        ``out``: a float32 (H, W) array (``depth`` itself too) to write it to, returned."""
    def sigma_m(self, depth_m: float) -> float: ...
    def reseed(self, seed: int) -> None: ...

def vrep_depth_buffer(
    depth: npt.ArrayLike, near_m: float, far_m: float
) -> npt.NDArray[np.float32]:
    """V-REP's depth buffer of a depth image (H, W) m, row 0 at the top: float32 (H, W), row 0
    the bottom row, (depth - near_m) / (far_m - near_m) in float64 clipped to [0, 1]."""

def detect_blobs(
    image: npt.ArrayLike, threshold: float = 0.5, min_size: float = 0.0
) -> npt.NDArray[np.float32]:
    """V-REP's blob detection on an image whose row 0 is the TOP.

    Object pixels: nonzero in a mask (H, W) uint8 or bool; (r + g + b) / 765 >= threshold in
    an RGB (H, W, 3) uint8 image. 8-connected blobs; those smaller than min_size (fraction of
    the image) are dropped; the rest come largest first. Returns V-REP's packet:
    [count, 6, then per blob: size (fraction of the image), orientation (rad, counter-clockwise
    with y up, meaningful modulo pi/2), x, y (centre of the smallest-area bounding rectangle,
    0..1, x from the left, y from the BOTTOM), width, height (that rectangle's sides over W and
    H, measured between pixel centres as V-REP does)]. Releases the GIL.
    """

class BatchWriter:
    """Non-blocking batched writes to many sockets, each with a backlog bounded by
    max_backlog_bytes and max_backlog_batches (oldest whole batches dropped, never a partly
    sent one)."""
    def __init__(self, max_backlog_bytes: int, max_backlog_batches: int = ...) -> None:
        """Default batches: no limit; ValueError for 0."""
    @property
    def max_backlog_batches(self) -> int: ...
    def open(self, fd: int, own: bool = True) -> int:
        """Start writing to a socket descriptor, duplicated when own (OSError past the
        descriptor limit), else borrowed; returns the connection's id (never reused)."""
    def close(self, id: int) -> None:
        """Forget a connection: its backlog goes, its duplicate descriptor is closed."""
    def queue(self, id: int, data: bytes) -> None:
        """Queue one whole batch (bytes-like, copied) for a connection."""
    def queue_slices(self, data: bytes, slices: npt.ArrayLike) -> None:
        """Queue bytes [begin, end) of data for each row (id, begin, end) of slices (M, 3);
        IndexError, queueing nothing, for a slice outside data."""
    def flush(self) -> list[tuple[int, int, bool]]:
        """Send what every socket takes now, without blocking; releases the GIL. Returns
        [(id, dropped_batches, failed)] for the connections where something went wrong."""
    def request_flush(self) -> None:
        """Ask the writer's own thread to flush what is queued now; returns at once."""
    def take_reports(self, wait: bool) -> list[tuple[int, int, bool]]:
        """The reports of the flushes the writer's thread finished since the last call."""
    def take_sent_bytes(self, wait: bool = True) -> list[tuple[int, int]]:
        """[(id, bytes)] sent since the last call that returned them; without wait, nothing
        while a flush is under way."""
    @property
    def backlog_bytes(self) -> int: ...
    @property
    def connection_count(self) -> int: ...
class TofSensorArray:
    """One VL53L0X time-of-flight sensor per robot (the e-puck2's ``dist_sens``): the distance
    along its pitched axis to the first surface, Gaussian noise of SD stddev_m + stddev_rel d
    from each robot's own stream (keyed by a stable robot id), clamped to [min, max]; max where
    nothing is within max."""

    def __init__(
        self,
        mount_m: npt.ArrayLike = ...,
        pitch_rad: float = -0.21,
        min_range_m: float = 0.005,
        max_range_m: float = 2.0,
        stddev_m: float = 0.003,
        stddev_rel: float = 0.02,
        seed: int = 0,
    ) -> None:
        """Mount (3,) in the body frame, m; pitch about body y, rad (negative looks up)."""
    def read(
        self,
        world: CollisionWorld,
        planar_poses: npt.ArrayLike,
        body_handles: Sequence[int],
        robot_ids: Sequence[int],
        noise: bool = True,
    ) -> npt.NDArray[np.float64]:
        """Ranges (N,) m of N robots at planar poses (N, 3) x, y, yaw. Releases the GIL."""
    def reseed(self, seed: int) -> None: ...

class BatchedWorlds:
    """B independent worlds of R e-pucks each (own obstacles, robots, noise streams, seed),
    stepped in one call without the GIL. Every per-robot array has N = B * R rows, row
    ``world * R + robot``. World b gives exactly the arrays of a standalone EpuckSwarm (seed
    seeds[b], robot r under handle ROBOT_HANDLE_BASE + r, added in order) on a CollisionWorld
    holding the same obstacles under handles 0, 1, ... in the order they were added. The
    output properties return fresh copies, filled in C++ by ``step``."""

    ROBOT_HANDLE_BASE: int  # 2**30: robot r's body handle in each world is this + r

    def __init__(
        self, model: EpuckModel, worlds: int, robots: int, seeds: Sequence[int]
    ) -> None:
        """Robots start on a 10 cm grid about the origin, heading 0, every noise off."""
    @property
    def worlds(self) -> int: ...
    @property
    def robots(self) -> int: ...
    @property
    def size(self) -> int:
        """N = worlds * robots."""
    @property
    def sensor_count(self) -> int: ...
    @property
    def frames(self) -> npt.NDArray[np.int64]:
        """(B,) steps of each world since it was built or reset."""
    def add_box(
        self,
        world: int,
        center: ArrayLike,
        half_extents: ArrayLike,
        yaw: float = 0.0,
        rgb: ArrayLike = ...,
    ) -> int:
        """A static box (group STATIC, as the arena's walls); returns its handle."""
    def add_cylinder(
        self, world: int, center: ArrayLike, radius: float, height: float, rgb: ArrayLike = ...
    ) -> int:
        """A static upright cylinder centred at center; returns its handle."""
    def clear_obstacles(self, world: int) -> None:
        """Removes a world's obstacles; handles start from 0 again."""
    def set_pose(self, world: int, robot: int, x: float, y: float, yaw: float) -> None:
        """Teleports a robot, odometry too, and clears its velocity history."""
    def reset_world(self, world: int, seed: int) -> None:
        """Frame 0, noise streams from seed, velocities and readings cleared; poses,
        obstacles and noise settings stay."""
    def set_ir_noise(
        self, probability: ArrayLike, mean_m: ArrayLike, stddev_m: ArrayLike
    ) -> None:
        """Each (N, K); all or nothing."""
    def set_imu_noise(self, accel_stddev: ArrayLike, gyro_stddev: ArrayLike) -> None:
        """Each (N, 3)."""
    def set_imu_bias(self, accel_bias: ArrayLike, gyro_bias: ArrayLike) -> None:
        """Each (N, 3)."""
    def set_slip_noise(self, stddev: ArrayLike) -> None:
        """(N,)."""
    def step(self, dt_s: float, wheel_cmd: ArrayLike) -> None:
        """Every world once; wheel_cmd (N, 2) rad/s, finite (ValueError before anything moves
        otherwise). Releases the GIL."""
    @property
    def poses(self) -> FloatArray:
        """(N, 3) x, y, yaw."""
    @property
    def velocities(self) -> FloatArray:
        """(N, 3) vx, vy (world), yaw rate."""
    @property
    def wheel_speeds(self) -> FloatArray:
        """(N, 2) rad/s after clamp and slip."""
    @property
    def odometry(self) -> FloatArray:
        """(N, 5) x, y, yaw, v, w."""
    @property
    def ranges(self) -> FloatArray:
        """(N, K) m, with noise."""
    @property
    def ranges_clean(self) -> FloatArray:
        """(N, K) m; max_range_m where nothing is detected."""
    @property
    def accel(self) -> FloatArray:
        """(N, 3) body-frame specific force, m/s^2."""
    @property
    def gyro(self) -> FloatArray:
        """(N, 3) rad/s."""
    @property
    def in_contact(self) -> BoolArray:
        """(N,) touched an obstacle or another robot during the last step."""
    def collision_world(self, world: int) -> CollisionWorld:
        """World b's collision world, for queries and rendering (do not change it)."""
    def swarm(self, world: int) -> EpuckSwarm:
        """World b's swarm, for its other outputs (do not step or change it)."""

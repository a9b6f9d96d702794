"""The cell's sensors: batched moves, ray proximity sensors, laser scanner, depth noise, blobs."""
import math
import numpy as np
import pytest
from conftest import GREY, IDENTITY, yaw_quaternion
from vrep_blobs import vrep_blobs

from epuck_vrep_compat import _core

# Sensor frame whose local +z (the proximity ray) points along world +y.
Z_TO_Y = (-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5))


def wall_at_y(world, handle, y, half_width=0.5):
    """A 2 cm thick wall whose near face is the plane y (for y > 0), 1 m high around z = 0."""
    world.add_box(handle, (half_width, 0.01, 0.5), (0, y + 0.01, 0), IDENTITY, GREY)


# --- CollisionWorld.set_poses -----------------------------------------------------------------

def test_set_poses_moves_every_object_and_rays_see_them(world):
    for handle in range(60):
        world.add_sphere(handle, 0.01, (0, 0, -1), IDENTITY, GREY)
    positions = np.column_stack([np.arange(60) * 0.1 + 1.0, np.zeros(60), np.zeros(60)])
    world.set_poses(np.arange(60), positions, np.tile(IDENTITY, (60, 1)))
    for handle in (0, 31, 59):
        assert np.allclose(world.get_pose(handle)[0], positions[handle])
    distance, hit, _ = world.ray_cast([[0, 0, 0]], [[1, 0, 0]], 10.0)
    assert hit[0] == 0 and distance[0] == pytest.approx(0.99, abs=1e-12)


def test_set_poses_is_all_or_nothing(world):
    world.add_sphere(1, 0.1, (0, 0, 0), IDENTITY, GREY)
    world.add_sphere(2, 0.1, (1, 0, 0), IDENTITY, GREY)
    moved = [[5, 5, 5], [6, 6, 6]]
    with pytest.raises(KeyError):
        world.set_poses([1, 9], moved, [IDENTITY, IDENTITY])
    with pytest.raises(ValueError, match="poses\\[1\\]: quaternion"):
        world.set_poses([1, 2], moved, [IDENTITY, (0, 0, 0, 0)])
    with pytest.raises(ValueError, match="poses\\[1\\]: position"):
        world.set_poses([1, 2], [[5, 5, 5], [math.nan, 0, 0]], [IDENTITY, IDENTITY])
    with pytest.raises(ValueError, match="quaternions"):
        world.set_poses([1, 2], moved, [IDENTITY])
    with pytest.raises(ValueError, match="handles"):
        world.set_poses([1], moved, [IDENTITY, IDENTITY])
    with pytest.raises(ValueError, match="handles"):
        world.set_poses([1.0, 2.0], moved, [IDENTITY, IDENTITY])
    assert np.allclose(world.get_pose(1)[0], (0, 0, 0))
    assert np.allclose(world.get_pose(2)[0], (1, 0, 0))


# --- RayProximityArray ------------------------------------------------------------------------

def test_proximity_reads_distance_point_normal_and_handle_in_the_sensor_frame(world):
    world.add_box(7, (0.5, 0.01, 0.5), (0, 0.06, 0), IDENTITY, GREY)  # face at y = 0.05
    sensors = _core.RayProximityArray([0.02, 0.02], [0.08, 0.08])
    # Sensor 0 looks along +y; sensor 1, turned a quarter about its own y axis, along +x.
    turned = (0.0, math.sqrt(0.5), 0.0, math.sqrt(0.5))
    detected, distance, point, handle, normal = sensors.read(
        world, [[0, 0, 0], [0, 0, 0]], [Z_TO_Y, turned], -1)
    assert detected.dtype == np.int32 and handle.dtype == np.int32
    assert list(detected) == [1, 0] and list(handle) == [7, -1]
    assert distance[0] == pytest.approx(0.05, abs=1e-12) and distance[1] == math.inf
    assert np.allclose(point, [[0, 0, 0.05], [0, 0, 0]], atol=1e-12)
    assert np.allclose(normal, [[0, 0, -1], [0, 0, 0]], atol=1e-12)


def test_proximity_detects_only_inside_its_range(world):
    wall_at_y(world, 1, 0.01)   # nearer than min: blinds, reads -inf
    wall_at_y(world, 2, 0.5)
    positions = [[0, 0.0, 0], [0, 0.3, 0], [0, 0.45, 0], [0, 0.421, 0], [0, 0.419, 0]]
    sensors = _core.RayProximityArray(np.full(5, 0.02), np.full(5, 0.08))
    detected, distance, _, handle, _ = sensors.read(world, positions, [Z_TO_Y] * 5)
    assert list(detected) == [0, 0, 1, 1, 0]
    assert distance[0] == -math.inf and distance[1] == math.inf
    assert distance[2] == pytest.approx(0.05) and distance[3] == pytest.approx(0.079)
    assert list(handle) == [-1, -1, 2, 2, -1]


def test_proximity_ignore_mask_and_noise(world):
    wall_at_y(world, 1, 0.03)
    world.add_box(2, (0.5, 0.01, 0.5), (0, 0.06, 0), IDENTITY, GREY, _core.GROUP_ROBOT)
    sensors = _core.RayProximityArray([0.02], [0.08])
    assert sensors.read(world, [[0, 0, 0]], [Z_TO_Y], [1])[3][0] == 2
    assert sensors.read(world, [[0, 0, 0]], [Z_TO_Y], mask=_core.GROUP_ROBOT)[3][0] == 2
    noisy = [_core.RayProximityArray(np.full(11, 0.02), np.full(11, 0.08), 0.002, seed=5)
             for _ in range(2)]
    positions, quaternions = np.zeros((11, 3)), np.tile(Z_TO_Y, (11, 1))
    readings = np.array([noisy[0].read(world, positions, quaternions)[1] for _ in range(1000)])
    assert abs(readings.mean() - 0.03) < 1e-4 and abs(readings.std() / 0.002 - 1) < 0.05
    again = np.array([noisy[1].read(world, positions, quaternions)[1] for _ in range(1000)])
    assert np.array_equal(readings, again)


@pytest.mark.parametrize("kwargs", [dict(min_range_m=[0.1], max_range_m=[0.05]),
                                    dict(min_range_m=[-0.1], max_range_m=[0.05]),
                                    dict(min_range_m=[0.0, 0.0], max_range_m=[0.05]),
                                    dict(noise_stddev_m=-1.0)])
def test_proximity_bad_construction(kwargs):
    arguments = dict(min_range_m=[0.02], max_range_m=[0.08])
    arguments.update(kwargs)
    with pytest.raises(ValueError):
        _core.RayProximityArray(**arguments)


def test_proximity_bad_read_arguments_are_named(world):
    sensors = _core.RayProximityArray([0.02, 0.02], [0.08, 0.08])
    with pytest.raises(ValueError, match="positions"):
        sensors.read(world, [[0, 0]] * 2, [IDENTITY] * 2)
    with pytest.raises(ValueError, match="quaternions"):
        sensors.read(world, [[0, 0, 0]] * 2, [IDENTITY])
    with pytest.raises(ValueError, match="ignore_handles"):
        sensors.read(world, [[0, 0, 0]] * 2, [IDENTITY] * 2, [1, 2, 3])
    with pytest.raises(ValueError, match="poses"):
        sensors.read(world, [[0, 0, 0]] * 3, [IDENTITY] * 3)


# --- LaserScanner -----------------------------------------------------------------------------

def beam_angles(scanner):
    return scanner.angle_min_rad + scanner.angle_increment_rad * np.arange(scanner.count)


def test_laser_sees_a_wall_at_its_range_and_bearing(world):
    wall_at_y(world, 1, 1.0, half_width=0.5)
    scanner = _core.LaserScanner()  # the Hokuyo: 682 beams, +-119.5 degrees, 0.02-5.6 m
    ranges = scanner.scan(world, (0, 0, 0), IDENTITY)
    assert ranges.dtype == np.float32 and ranges.shape == (682,)
    angles = beam_angles(scanner)
    left = int(np.argmin(np.abs(angles - math.pi / 2)))
    assert angles[left] == pytest.approx(math.pi / 2) and ranges[left] == pytest.approx(1.0)
    wall_x = np.abs(np.cos(angles)) / np.maximum(np.sin(angles), 1e-12)  # where y = 1 is met
    on_wall = (angles > 0) & (wall_x < 0.49)
    assert np.allclose(ranges[on_wall], 1.0 / np.sin(angles[on_wall]), rtol=1e-6)
    assert np.all(ranges[(angles <= 0) | (wall_x > 0.51)] == np.inf)
    # Turned by +90 degrees, the wall moves to the front beam.
    ranges = scanner.scan(world, (0, 0, 0), yaw_quaternion(math.pi / 2))
    front = int(np.argmin(np.abs(angles)))
    assert ranges[front] == pytest.approx(1.0) and ranges[left] == np.inf


def test_laser_empty_world_too_close_and_mask(world):
    scanner = _core.LaserScanner(angle_min_rad=-0.1, angle_increment_rad=0.1, count=3,
                                 range_min_m=0.05, range_max_m=2.0)
    assert np.all(scanner.scan(world, (0, 0, 0), IDENTITY) == np.inf)
    world.add_box(1, (0.01, 0.5, 0.5), (0.03, 0, 0), IDENTITY, GREY, _core.GROUP_ROBOT)
    world.add_box(2, (0.01, 0.5, 0.5), (1.01, 0, 0), IDENTITY, GREY)
    assert np.all(scanner.scan(world, (0, 0, 0), IDENTITY) == -np.inf)
    ranges = scanner.scan(world, (0, 0, 0), IDENTITY, ignore_handle=1)
    assert ranges[1] == pytest.approx(1.0)
    assert np.array_equal(scanner.scan(world, (0, 0, 0), IDENTITY, mask=_core.GROUP_STATIC),
                          ranges)
    # A scan plane that passes above both boxes sees nothing.
    assert np.all(scanner.scan(world, (0, 0, 0.6), IDENTITY) == np.inf)


def test_laser_equals_one_ray_cast_per_beam(world):
    rng = np.random.default_rng(3)
    for handle in range(40):
        position = (*rng.uniform(-3, 3, 2), rng.uniform(-0.3, 0.3))
        quaternion = rng.normal(size=4)
        if handle % 3 == 0:
            world.add_box(handle, rng.uniform(0.05, 0.3, 3), position, quaternion, GREY)
        elif handle % 3 == 1:
            world.add_cylinder(handle, 0.1, 0.5, position, quaternion, GREY)
        else:
            world.add_sphere(handle, rng.uniform(0.05, 0.3), position, quaternion, GREY)
    scanner = _core.LaserScanner(range_min_m=0.0, range_max_m=4.0)
    tilt = np.array([0.1, -0.05, 0.3, 1.0]) / np.linalg.norm([0.1, -0.05, 0.3, 1.0])
    ranges = scanner.scan(world, (0.2, -0.1, 0.05), tilt)
    x, y, z, w = tilt
    rotation = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    angles = beam_angles(scanner)
    local = np.column_stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)])
    expected, _, _ = world.ray_cast(np.tile((0.2, -0.1, 0.05), (682, 1)), local @ rotation.T,
                                    4.0)
    assert np.isfinite(ranges).sum() > 100
    assert np.array_equal(np.isinf(ranges), np.isinf(expected))
    assert np.allclose(ranges, expected, rtol=1e-6, atol=0)


@pytest.mark.parametrize("distance, sigma", [(0.5, 0.01), (3.0, 0.03)])
def test_laser_noise_statistics(world, distance, sigma):
    world.add_box(1, (0.01, 1, 1), (distance + 0.01, 0, 0), IDENTITY, GREY)
    # 10 000 beams within 1e-4 rad of the wall's normal: one scan, 10 000 samples.
    scanner = _core.LaserScanner(angle_min_rad=0.0, angle_increment_rad=1e-8, count=10000,
                                 sigma_min_m=0.01, sigma_rel=0.01, seed=7)
    ranges = scanner.scan(world, (0, 0, 0), IDENTITY).astype(float)
    assert abs(ranges.mean() - distance) < 4 * sigma / 100
    assert abs(ranges.std() / sigma - 1) < 0.1


def test_laser_noise_is_deterministic_per_seed(world):
    wall_at_y(world, 1, 1.0, half_width=3.0)
    scans = [_core.LaserScanner(sigma_min_m=0.01, sigma_rel=0.01, seed=s) for s in (1, 1, 2)]
    first, same, other = (s.scan(world, (0, 0, 0), IDENTITY) for s in scans)
    assert np.array_equal(first, same) and not np.array_equal(first, other)
    second = scans[0].scan(world, (0, 0, 0), IDENTITY)
    assert not np.array_equal(first, second)
    scans[0].reseed(1)
    assert np.array_equal(scans[0].scan(world, (0, 0, 0), IDENTITY), first)


@pytest.mark.parametrize("kwargs", [dict(count=0), dict(range_min_m=2.0, range_max_m=1.0),
                                    dict(sigma_rel=-0.1), dict(angle_min_rad=math.inf),
                                    dict(sigma_min_m=math.nan)])
def test_laser_bad_construction(kwargs):
    with pytest.raises(ValueError):
        _core.LaserScanner(**kwargs)


def test_laser_bad_pose_is_named(world):
    scanner = _core.LaserScanner()
    with pytest.raises(ValueError, match="position"):
        scanner.scan(world, (0, 0), IDENTITY)
    with pytest.raises(ValueError, match="quaternion"):
        scanner.scan(world, (0, 0, 0), (0, 0, 0, 0))


# --- DepthNoise -------------------------------------------------------------------------------

def test_depth_noise_sigma_grows_with_depth():
    noise = _core.DepthNoise(seed=3)
    for z in (1.0, 4.0):
        expected = 0.0012 + 0.0019 * (z - 0.4) ** 2
        assert noise.sigma_m(z) == pytest.approx(expected)
        noisy = noise.apply(np.full((480, 640), z, np.float32), 0.5, 8.0)
        assert noisy.dtype == np.float32 and noisy.shape == (480, 640)
        offsets = noisy.astype(float) - np.float32(z)
        assert abs(offsets.mean()) < 4 * expected / math.sqrt(offsets.size)
        assert abs(offsets.std() / expected - 1) < 0.02
        # A normal's tails: |n| > 3 sigma for 0.27 % of pixels.
        assert abs(np.mean(np.abs(offsets) > 3 * expected) - 0.0027) < 0.0005


def test_depth_noise_keeps_no_return_and_clamps():
    depth = np.array([[0.5, 5.0, 6.0, np.inf]], np.float32)
    noisy = _core.DepthNoise(a_m=1.0, seed=1).apply(depth, 0.5, 5.0)
    assert noisy[0, 1] == 5.0 and noisy[0, 2] == 5.0 and noisy[0, 3] == 5.0
    assert np.all((noisy >= 0.5) & (noisy <= 5.0))


def test_depth_noise_is_deterministic_per_seed_and_off_when_zero():
    depth = np.random.default_rng(1).uniform(0.5, 4.0, (60, 80)).astype(np.float32)
    first, same, other = (_core.DepthNoise(seed=s).apply(depth, 0.4, 5.0) for s in (4, 4, 5))
    assert np.array_equal(first, same) and not np.array_equal(first, other)
    noise = _core.DepthNoise(seed=4)
    noise.apply(depth, 0.4, 5.0)
    noise.reseed(4)
    assert np.array_equal(noise.apply(depth, 0.4, 5.0), first)
    silent = _core.DepthNoise(a_m=0.0, b_per_m=0.0)
    assert np.array_equal(silent.apply(depth, 0.4, 5.0), depth)


def test_depth_quantisation_rounds_inverse_depth():
    step = 1 / 8 / (580 * 0.075)  # Kinect: 1/8 px disparity, f = 580 px, b = 7.5 cm
    depth = np.linspace(0.6, 4.9, 5000, dtype=np.float32).reshape(50, 100)
    quantised = _core.DepthNoise(a_m=0.0, b_per_m=0.0, inverse_depth_step_per_m=step)
    levels = 1.0 / (step * quantised.apply(depth, 0.4, 5.0).astype(float))
    assert np.allclose(levels, np.round(levels), atol=1e-3)
    steps = np.diff(np.unique(quantised.apply(depth, 0.4, 5.0)))
    assert steps.max() == pytest.approx(step * 4.9 ** 2, rel=0.05)  # ~7 cm at 5 m


@pytest.mark.parametrize("depth, near, far, name", [
    (np.array([[1.0, np.nan]]), 0.1, 5.0, "depth"), (np.array([[-1.0]]), 0.1, 5.0, "depth"),
    (np.ones(3), 0.1, 5.0, "depth"), (np.ones((2, 2)), 5.0, 1.0, "near_m")])
def test_depth_noise_bad_arguments(depth, near, far, name):
    with pytest.raises(ValueError, match=name):
        _core.DepthNoise().apply(depth, near, far)
    with pytest.raises(ValueError, match="b_per_m"):
        _core.DepthNoise(b_per_m=-1.0)


# --- detect_blobs -----------------------------------------------------------------------------

def blobs_of(packet):
    """The packet's blobs as rows (size, orientation, x, y, width, height)."""
    count, values = int(packet[0]), int(packet[1])
    assert values == 6 and packet.size == 2 + 6 * count
    return packet[2:].reshape(count, 6).astype(float)


def disc(height, width, row, col, radius):
    rows, cols = np.mgrid[:height, :width]
    return (rows - row) ** 2 + (cols - col) ** 2 <= radius ** 2


def test_one_disc_centre_size_and_bottom_origin():
    mask = disc(128, 128, 30, 90, 12).astype(np.uint8) * 255  # upper right
    packet = _core.detect_blobs(mask)
    assert packet.dtype == np.float32
    (size, _, x, y, width, height), = blobs_of(packet)
    assert size == pytest.approx(mask.astype(bool).sum() / 128 ** 2, rel=1e-6)
    assert x == pytest.approx((90 + 0.5) / 128, abs=1e-6)
    assert y == pytest.approx((128 - 30 - 0.5) / 128, abs=1e-6)  # counted from the bottom
    assert 22 / 128 <= min(width, height) and max(width, height) <= 25 / 128


def test_blobs_come_largest_first_and_small_ones_drop():
    mask = disc(100, 100, 80, 20, 6) | disc(100, 100, 20, 70, 15)
    mask[50, 50] = True  # one pixel: 1e-4 of the image
    blobs = blobs_of(_core.detect_blobs(mask))
    assert len(blobs) == 3 and blobs[0, 0] > blobs[1, 0] > blobs[2, 0]
    assert blobs[0, 2:4] == pytest.approx([0.705, 0.795]) and blobs[2, 2:4] == pytest.approx(
        [0.505, 0.495])
    assert len(blobs_of(_core.detect_blobs(mask, min_size=2e-4))) == 2


def test_empty_image_and_eight_connectivity():
    assert list(_core.detect_blobs(np.zeros((20, 30), np.uint8))) == [0, 6]
    diagonal = np.eye(10, dtype=bool)
    (size, orientation, x, y, width, height), = blobs_of(_core.detect_blobs(diagonal))
    assert size == pytest.approx(0.1) and x == pytest.approx(0.5) and y == pytest.approx(0.5)
    # A falling diagonal (row 0 top-left) is a line at -45 degrees, modulo 90.
    assert math.remainder(orientation + math.pi / 4, math.pi / 2) == pytest.approx(0, abs=0.02)
    assert min(width, height) == pytest.approx(0.0, abs=0.01)


@pytest.mark.parametrize("degrees", [0.0, 20.0, 30.0, 60.0, -35.0])
def test_orientation_and_sides_of_a_turned_rectangle(degrees):
    rows, cols = np.mgrid[:200, :200]
    x, y = cols - 100.0, 99.0 - rows  # y up, as V-REP's image
    a = math.radians(degrees)
    along, across = x * math.cos(a) + y * math.sin(a), -x * math.sin(a) + y * math.cos(a)
    mask = (np.abs(along) <= 40) & (np.abs(across) <= 10)
    (_, orientation, cx, cy, width, height), = blobs_of(_core.detect_blobs(mask))
    assert math.remainder(orientation - a, math.pi / 2) == pytest.approx(0, abs=math.radians(1.5))
    assert sorted([width * 200, height * 200]) == pytest.approx([20, 80], abs=1.5)
    assert (cx, cy) == pytest.approx((100.5 / 200, 100.5 / 200), abs=1 / 200)


def test_rgb_images_use_the_intensity_threshold():
    image = np.zeros((40, 40, 3), np.uint8)
    image[5:15, 5:15] = (255, 255, 255)
    image[25:35, 25:35] = (90, 90, 90)  # intensity 0.35
    assert blobs_of(_core.detect_blobs(image, threshold=0.5)).shape[0] == 1
    assert blobs_of(_core.detect_blobs(image, threshold=0.3)).shape[0] == 2


@pytest.mark.parametrize("seed", range(4))
def test_blobs_equal_vrep_reference_on_random_images(seed):
    rng = np.random.default_rng(seed)
    mask = rng.random((48, 64)) < 0.45
    min_size = 3 / mask.size
    assert np.array_equal(blobs_of(_core.detect_blobs(mask, min_size=min_size)),
                          vrep_blobs(mask, min_size))


@pytest.mark.parametrize("image", [np.zeros((4, 4), np.float32), np.zeros((4, 4, 2), np.uint8),
                                   np.zeros(4, np.uint8), np.zeros((0, 4), np.uint8)])
def test_blob_bad_images(image):
    with pytest.raises(ValueError, match="image"):
        _core.detect_blobs(image)

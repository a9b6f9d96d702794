"""BatchedWorlds: each world is exactly a standalone EpuckSwarm on a CollisionWorld (the parity
the learning environments rely on), worlds are independent, one world resets alone, runs repeat
per seed, contacts are reported, bad input is refused before anything changes."""
import math

import numpy as np
import pytest

from epuck_vrep_compat import _core
from epuck_vrep_compat.epuck.noise import NoiseSettings

DT = 0.05
HALF = 0.25          # the arena's half side, m
OUTPUTS = ("poses", "velocities", "wheel_speeds", "odometry", "ranges", "ranges_clean", "accel",
           "gyro", "in_contact")
# The arena: four walls (box centre, half extents) and two cylinders (centre, radius, height).
WALLS = [((HALF + 0.005, 0.0, 0.05), (0.005, HALF, 0.05)),
         ((-HALF - 0.005, 0.0, 0.05), (0.005, HALF, 0.05)),
         ((0.0, HALF + 0.005, 0.05), (HALF, 0.005, 0.05)),
         ((0.0, -HALF - 0.005, 0.05), (HALF, 0.005, 0.05))]
CYLINDERS = [((0.1, 0.12, 0.05), 0.03, 0.1), ((-0.12, -0.1, 0.04), 0.02, 0.08)]
TILTED_BOX = ((0.0, 0.0, 0.02), (0.03, 0.01, 0.02), 0.6)


def start_pose(world, robot):
    """Robots 8 cm apart on a row, each world's row at its own height and headings."""
    return -0.18 + 0.08 * robot, -0.15 + 0.07 * (world % 4), 0.4 * robot + world


def noise(n):
    """Every noise source on, N rows each."""
    return {"ir": (np.full((n, 8), 0.5), np.full((n, 8), 0.002), np.full((n, 8), 0.001)),
            "imu": (np.full((n, 3), 0.05), np.full((n, 3), 0.01)),
            "bias": (np.full((n, 3), 0.02), np.full((n, 3), -0.001)),
            "slip": np.full(n, 0.05)}


def set_noise(target, n):
    settings = noise(n)
    target.set_ir_noise(*settings["ir"])
    target.set_imu_noise(*settings["imu"])
    target.set_imu_bias(*settings["bias"])
    target.set_slip_noise(settings["slip"])


def batch(worlds=3, robots=4, seeds=(11, 12, 13)):
    """The arena in every world, robots at start_pose, every noise on."""
    batched = _core.BatchedWorlds(_core.EpuckModel(), worlds, robots, list(seeds[:worlds]))
    for w in range(worlds):
        for center, half in WALLS:
            batched.add_box(w, center, half)
        for center, radius, height in CYLINDERS:
            batched.add_cylinder(w, center, radius, height)
        batched.add_box(w, *TILTED_BOX)
        for r in range(robots):
            batched.set_pose(w, r, *start_pose(w, r))
    set_noise(batched, batched.size)
    return batched


def standalone(world, robots, seed):
    """The same world built as the simulator builds one: obstacles first, then the robots."""
    collision = _core.CollisionWorld()
    grey = (0.6, 0.6, 0.6)
    for handle, (center, half) in enumerate(WALLS):
        collision.add_box(handle, half, center, (0, 0, 0, 1), grey)
    for handle, (center, radius, height) in enumerate(CYLINDERS, len(WALLS)):
        collision.add_cylinder(handle, radius, height, center, (0, 0, 0, 1), grey)
    center, half, yaw = TILTED_BOX
    # C's sin and cos, as the core turns a yaw into a quaternion (numpy's may differ by an ulp)
    collision.add_box(len(WALLS) + len(CYLINDERS), half, center,
                      (0, 0, math.sin(yaw / 2), math.cos(yaw / 2)), grey)
    swarm = _core.EpuckSwarm(collision, _core.EpuckModel(), seed)
    for r in range(robots):
        x, y, yaw = start_pose(world, r)
        swarm.add_robot(_core.BatchedWorlds.ROBOT_HANDLE_BASE + r, x, y, yaw)
    set_noise(swarm, robots)
    return swarm


def commands(steps, n, seed=5):
    return np.random.default_rng(seed).uniform(-7.0, 7.0, (steps, n, 2))


def rows(batched, world):
    return slice(world * batched.robots, (world + 1) * batched.robots)


def snapshot(target, part=slice(None)):
    return {name: getattr(target, name)[part] for name in OUTPUTS}


def assert_same(a, b, where=""):
    for name in OUTPUTS:
        assert np.array_equal(a[name], b[name]), f"{where} {name}"


def test_each_world_is_a_standalone_swarm_bit_for_bit():
    batched = batch()
    swarms = [standalone(w, 4, seed) for w, seed in enumerate((11, 12, 13))]
    touched = 0
    for step, command in enumerate(commands(400, batched.size)):
        batched.step(DT, command)
        for w, swarm in enumerate(swarms):
            swarm.step(DT, command[rows(batched, w)])
            assert_same(snapshot(batched, rows(batched, w)), snapshot(swarm), f"step {step}")
        touched += batched.in_contact.sum()
    assert touched > 50   # the parity covers contacts with walls, cylinders and robots
    assert list(batched.frames) == [400] * 3


def test_driving_one_world_into_a_wall_changes_nothing_of_another():
    calm, crashed = batch(), batch()
    moves = commands(200, calm.size)
    for command in moves:
        calm.step(DT, command)
        rammed = command.copy()
        rammed[rows(crashed, 0)] = 7.0          # world 0's robots straight ahead, into a wall
        crashed.step(DT, rammed)
        for w in (1, 2):
            assert_same(snapshot(calm, rows(calm, w)), snapshot(crashed, rows(crashed, w)))
    assert crashed.in_contact[rows(crashed, 0)].all()


def test_resetting_one_world_repeats_its_first_run_and_leaves_the_others_alone():
    batched, untouched = batch(), batch()
    first, second = commands(150, batched.size, 1), commands(150, batched.size, 2)
    world0 = rows(batched, 0)
    recorded = []
    for command in first:
        batched.step(DT, command)
        untouched.step(DT, command)
        recorded.append(snapshot(batched, world0))
    batched.reset_world(0, 11)
    for r in range(batched.robots):
        batched.set_pose(0, r, *start_pose(0, r))
    assert list(batched.frames) == [0, 150, 150]
    assert not batched.velocities[world0].any()
    for step, command in enumerate(second):
        command[world0] = first[step][world0]
        batched.step(DT, command)
        untouched.step(DT, command)
        assert_same(snapshot(batched, world0), recorded[step], f"step {step}")
        others = slice(batched.robots, None)
        assert_same(snapshot(batched, others), snapshot(untouched, others), f"step {step}")


def test_same_seeds_same_arrays_other_seeds_other_noise():
    runs = [batch(seeds=seeds) for seeds in ((1, 2, 3), (1, 2, 3), (1, 2, 4))]
    for command in commands(100, runs[0].size):
        for run in runs:
            run.step(DT, command)
    assert_same(snapshot(runs[0]), snapshot(runs[1]))
    last = rows(runs[0], 2)
    assert np.array_equal(runs[0].ranges[:last.start], runs[2].ranges[:last.start])
    assert not np.array_equal(runs[0].ranges[last], runs[2].ranges[last])


def test_contacts_with_walls_robots_and_nothing():
    batched = _core.BatchedWorlds(_core.EpuckModel(), 2, 2, [0, 0])
    batched.add_box(0, (0.1, 0.0, 0.05), (0.01, 0.5, 0.05))
    batched.set_pose(0, 0, 0.05, 0.0, 0.0)     # 1.3 cm short of the wall, heading at it
    batched.set_pose(0, 1, -0.5, 0.0, 0.0)     # alone in the open
    batched.set_pose(1, 0, 0.0, 0.0, 0.0)      # two robots nose to nose, 1 cm apart
    batched.set_pose(1, 1, 0.08, 0.0, np.pi)
    assert not batched.in_contact.any()
    for _ in range(5):
        batched.step(DT, np.full((4, 2), 5.0))
    assert batched.in_contact.tolist() == [True, False, True, True]
    batched.step(DT, np.zeros((4, 2)))         # resting against what it touched
    assert not batched.in_contact.any()


def test_outputs_are_copies_and_follow_set_pose():
    batched = _core.BatchedWorlds(_core.EpuckModel(), 2, 3, [0, 1])
    poses = batched.poses
    poses[:] = 99.0
    assert (batched.poses != 99.0).all()
    batched.set_pose(1, 2, 0.3, -0.2, 0.5)
    assert batched.poses[5].tolist() == [0.3, -0.2, 0.5]
    assert batched.odometry[5, :3].tolist() == [0.3, -0.2, 0.5]
    assert batched.ranges.shape == (6, 8) and batched.in_contact.dtype == bool
    assert batched.frames.dtype == np.int64


def test_obstacles_clear_and_their_handles_start_over():
    batched = _core.BatchedWorlds(_core.EpuckModel(), 1, 1, [0])
    assert batched.add_box(0, (0.06, 0.0, 0.05), (0.005, 0.1, 0.05)) == 0
    assert batched.add_cylinder(0, (-0.3, 0.0, 0.05), 0.02, 0.1) == 1
    batched.step(DT, np.zeros((1, 2)))
    assert batched.ranges_clean[0, 0] < 0.05
    batched.clear_obstacles(0)
    batched.step(DT, np.zeros((1, 2)))
    assert (batched.ranges_clean == _core.EpuckModel().sensors[0].max_range_m).all()
    assert batched.add_box(0, (1.0, 0.0, 0.05), (0.005, 0.1, 0.05)) == 0
    assert batched.collision_world(0).handles() == [0, _core.BatchedWorlds.ROBOT_HANDLE_BASE]


def test_noise_settings_apply_to_every_row():
    batched = _core.BatchedWorlds(_core.EpuckModel(), 2, 2, [3, 4])
    swarms = []
    for w in range(2):
        swarm = _core.EpuckSwarm(_core.CollisionWorld(), _core.EpuckModel(), 3 + w)
        swarms.append(swarm)
        for r in range(2):
            x, y, _yaw = batched.poses[2 * w + r]
            swarm.add_robot(_core.BatchedWorlds.ROBOT_HANDLE_BASE + r, x, y, 0.0)
        NoiseSettings().apply(swarm, ["a", "b"])
    NoiseSettings().apply(batched, ["a", "b", "c", "d"])
    for command in commands(50, 4):
        batched.step(DT, command)
        for w, swarm in enumerate(swarms):
            swarm.step(DT, command[2 * w:2 * w + 2])
            assert_same(snapshot(batched, slice(2 * w, 2 * w + 2)), snapshot(swarm))


def test_a_refused_setting_changes_no_world():
    batched, reference = batch(), batch()
    n = batched.size
    bad = np.full((n, 8), 0.5)
    bad[-1, -1] = 1.5                            # the last world's last sensor only
    with pytest.raises(ValueError):
        batched.set_ir_noise(bad, np.zeros((n, 8)), np.zeros((n, 8)))
    with pytest.raises(ValueError):
        batched.set_slip_noise(np.r_[np.zeros(n - 1), -1.0])
    for command in commands(30, n):
        batched.step(DT, command)
        reference.step(DT, command)
    assert_same(snapshot(batched), snapshot(reference))


@pytest.mark.parametrize("make, error, message", [
    (lambda m: _core.BatchedWorlds(m, 2, 1, [0]), ValueError, "one seed per world"),
    (lambda m: _core.BatchedWorlds(m, 0, 1, []), ValueError, ">= 1"),
    (lambda m: _core.BatchedWorlds(m, 1, 0, [0]), ValueError, ">= 1"),
    (lambda m: _core.BatchedWorlds(_core.EpuckModel(sensors=[]), 1, 1, [0]), ValueError, ""),
])
def test_bad_construction_is_refused(make, error, message):
    with pytest.raises(error, match=message):
        make(_core.EpuckModel())


@pytest.mark.parametrize("call, error, message", [
    (lambda b: b.step(DT, np.zeros((3, 2))), ValueError, r"shape \(4, 2\)"),
    (lambda b: b.step(DT, np.full((4, 2), np.nan)), ValueError, "finite"),
    (lambda b: b.step(0.0, np.zeros((4, 2))), ValueError, "dt_s"),
    (lambda b: b.step(np.inf, np.zeros((4, 2))), ValueError, "dt_s"),
    (lambda b: b.set_pose(2, 0, 0.0, 0.0, 0.0), IndexError, "world index 2"),
    (lambda b: b.set_pose(-1, 0, 0.0, 0.0, 0.0), IndexError, "world index -1"),
    (lambda b: b.set_pose(0, 2, 0.0, 0.0, 0.0), IndexError, "robot index 2"),
    (lambda b: b.set_pose(0, 0, np.nan, 0.0, 0.0), ValueError, "finite"),
    (lambda b: b.reset_world(5, 0), IndexError, "world index 5"),
    (lambda b: b.clear_obstacles(2), IndexError, "world index"),
    (lambda b: b.add_box(0, (np.inf, 0, 0), (1, 1, 1)), ValueError, "center"),
    (lambda b: b.add_box(0, (0, 0, 0), (1, 0, 1)), ValueError, "half_extents"),
    (lambda b: b.add_box(0, (0, 0, 0), (1, 1)), ValueError, "half_extents"),
    (lambda b: b.add_box(0, (0, 0, 0), (1, 1, 1), np.nan), ValueError, "yaw"),
    (lambda b: b.add_cylinder(0, (0, 0, 0), -1.0, 0.1), ValueError, "radius"),
    (lambda b: b.add_cylinder(3, (0, 0, 0), 1.0, 0.1), IndexError, "world index 3"),
    (lambda b: b.set_ir_noise(*[np.zeros((2, 8))] * 3), ValueError, r"shape \(4, 8\)"),
    (lambda b: b.set_imu_noise(np.zeros((4, 3)), np.zeros((4, 2))), ValueError, "gyro"),
    (lambda b: b.set_imu_bias(np.full((4, 3), np.nan), np.zeros((4, 3))), ValueError, "bias"),
    (lambda b: b.set_slip_noise(np.zeros(3)), ValueError, r"shape \(4,\)"),
])
def test_bad_input_is_refused_before_anything_changes(call, error, message):
    batched = _core.BatchedWorlds(_core.EpuckModel(), 2, 2, [0, 1])
    before = snapshot(batched)
    with pytest.raises(error, match=message):
        call(batched)
    assert_same(snapshot(batched), before)
    assert list(batched.frames) == [0, 0]

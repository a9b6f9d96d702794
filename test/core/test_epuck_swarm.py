"""EpuckSwarm: determinism, independent noise streams, outputs, validation, cost per step."""
import math
import time

import numpy as np
import pytest
from conftest import GREY, IDENTITY, add_arena, still, yaw_quaternion

from epuck_vrep_compat import _core

DT = 0.05
ROBOTS = [(100 + i, -0.2 + 0.1 * i, 0.02 * (-1) ** i, 0.7 * i) for i in range(5)]  # 3 cm gaps


def arena_swarm(half_size_m, seed):
    """The five ROBOTS in a walled square (the swarm keeps its world alive)."""
    world = _core.CollisionWorld()
    add_arena(world, half_size_m)
    swarm = _core.EpuckSwarm(world, _core.EpuckModel(), seed)
    for robot in ROBOTS:
        swarm.add_robot(*robot)
    return swarm


def noisy_run(seed, steps, reseed=None):
    """Five robots in a small arena with every noise source on; returns the final swarm."""
    swarm = arena_swarm(0.25, seed)
    n = swarm.size
    swarm.set_ir_noise(np.full((n, 8), 0.5), np.full((n, 8), 0.002), np.full((n, 8), 0.001))
    swarm.set_imu_noise(np.full((n, 3), 0.05), np.full((n, 3), 0.01))
    swarm.set_slip_noise(np.full(n, 0.05))
    if reseed is not None:
        swarm.reseed(reseed)
    commands = np.random.default_rng(1234).uniform(-7.0, 7.0, (steps, n, 2))
    for command in commands:
        swarm.step(DT, command)
    return swarm


def test_same_seed_is_bit_identical_after_1000_steps():
    a, b = noisy_run(7, 1000), noisy_run(7, 1000)
    for name in ("poses", "ranges", "ranges_clean", "accel", "gyro", "odometry", "velocities"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.frame == 1000


def test_reset_and_rerun_is_bit_identical():
    swarm = arena_swarm(0.2, 3)
    swarm.set_slip_noise(np.full(swarm.size, 0.05))
    swarm.set_ir_noise(*(np.full((swarm.size, 8), v) for v in (0.5, 0.002, 0.001)))
    commands = np.random.default_rng(5).uniform(-7.0, 7.0, (300, swarm.size, 2))

    def run():
        for i, (_, x, y, yaw) in enumerate(ROBOTS):
            swarm.set_pose(i, x, y, yaw)
        swarm.reseed(3)
        for command in commands:
            swarm.step(DT, command)
        return swarm.poses, swarm.ranges, swarm.accel

    first, second = run(), run()
    assert all(np.array_equal(a, b) for a, b in zip(first, second))


def test_ir_noise_turned_on_mid_run_draws_as_if_it_had_drawn_all_along():
    # With probability 0 the step skips the IR draws and makes them up before the next one
    # that counts; a probability too small ever to apply draws every time: the same stream.
    def run(probability_before):
        swarm = arena_swarm(0.2, 11)
        n = swarm.size
        commands = np.random.default_rng(8).uniform(-7.0, 7.0, (60, n, 2))
        swarm.set_ir_noise(np.full((n, 8), probability_before), np.zeros((n, 8)),
                           np.zeros((n, 8)))
        for command in commands[:30]:
            swarm.step(DT, command)
        swarm.set_ir_noise(np.full((n, 8), 0.5), np.full((n, 8), 0.002),
                           np.full((n, 8), 0.001))
        for command in commands[30:]:
            swarm.step(DT, command)
        return swarm.ranges, swarm.ranges_clean

    (skipped, clean), (drawn, _) = run(0.0), run(1e-300)
    assert np.array_equal(skipped, drawn)
    assert not np.array_equal(skipped, clean)  # the draws after the switch made some noisy


def test_different_seed_gives_different_noisy_ranges():
    assert not np.array_equal(noisy_run(7, 50).ranges, noisy_run(8, 50).ranges)


def test_reseed_reproduces_a_run():
    a, b = noisy_run(7, 200), noisy_run(99, 200, reseed=7)
    assert np.array_equal(a.poses, b.poses) and np.array_equal(a.ranges, b.ranges)


def test_reset_repeats_the_run_after_the_robots_were_added():
    swarm = arena_swarm(0.25, 3)
    n = swarm.size
    swarm.set_slip_noise(np.full(n, 0.05))
    swarm.set_ir_noise(*(np.full((n, 8), v) for v in (0.5, 0.002, 0.001)))
    swarm.set_imu_noise(np.full((n, 3), 0.05), np.full((n, 3), 0.01))
    names = ("poses", "ranges", "accel", "gyro", "odometry", "velocities", "wheel_angles",
             "in_contact")
    commands = np.random.default_rng(5).uniform(-7.0, 7.0, (200, n, 2))

    def run():
        recorded = []
        for command in commands:
            swarm.step(DT, command)
            recorded.append([getattr(swarm, name) for name in names])
        return recorded

    first = run()
    for i, (_, x, y, yaw) in enumerate(ROBOTS):
        swarm.set_pose(i, x, y, yaw)
    swarm.reset(3)
    assert swarm.frame == 0 and not swarm.in_contact.any()
    assert not swarm.wheel_angles.any() and not swarm.velocities.any()
    for step, (a, b) in enumerate(zip(first, run())):
        assert all(np.array_equal(x, y) for x, y in zip(a, b)), step
    assert any(record[-1].any() for record in first)   # contacts took part


def test_a_robots_noise_does_not_depend_on_the_others(world):
    add_arena(world, 0.1)

    def run(count):
        swarm = _core.EpuckSwarm(world, _core.EpuckModel(), 5)
        for i in range(count):
            swarm.add_robot(200 * (count + 1) + i, 50.0 * i + 10 * count, 0.0, 0.0)
        swarm.set_ir_noise(np.full((count, 8), 1.0), np.full((count, 8), 0.003),
                           np.full((count, 8), 0.001))
        for _ in range(20):
            swarm.step(DT, still(swarm))
        return swarm.ranges[0]

    assert np.array_equal(run(1), run(3))


def test_output_shapes_and_types(make_swarm):
    swarm = make_swarm(ROBOTS)
    swarm.step(DT, still(swarm))
    n = len(ROBOTS)
    shapes = dict(poses=(n, 3), velocities=(n, 3), wheel_speeds=(n, 2), wheel_angles=(n, 2),
                  odometry=(n, 5), ranges_clean=(n, 8), ranges=(n, 8), detected_handles=(n, 8),
                  detected_points=(n, 8, 3), detected_normals=(n, 8, 3), accel=(n, 3),
                  gyro=(n, 3), handles=(n,))
    for name, shape in shapes.items():
        assert getattr(swarm, name).shape == shape, name
    assert swarm.detected_handles.dtype == np.int32 and swarm.handles.dtype == np.int32
    assert list(swarm.handles) == [r[0] for r in ROBOTS]
    assert swarm.size == n and swarm.frame == 1
    # Neighbours are in range; a robot never sees itself.
    assert (swarm.detected_handles >= 100).any()
    assert not (swarm.detected_handles == swarm.handles[:, None]).any()


def test_ir_noise_applies_and_stays_in_range(make_swarm):
    swarm = make_swarm(ROBOTS)
    n = swarm.size
    swarm.set_ir_noise(np.ones((n, 8)), np.full((n, 8), 0.01), np.full((n, 8), 0.01))
    swarm.step(DT, still(swarm))
    assert not np.array_equal(swarm.ranges, swarm.ranges_clean)
    assert swarm.ranges.min() >= 0.0015 and swarm.ranges.max() <= 0.05


@pytest.mark.parametrize(
    "setter, arguments",
    [("set_ir_noise", (np.full((1, 8), 1.5), np.zeros((1, 8)), np.zeros((1, 8)))),
     ("set_ir_noise", (np.zeros((1, 8)), np.zeros((1, 8)), np.full((1, 8), -0.1))),
     ("set_ir_noise", (np.zeros((1, 7)), np.zeros((1, 7)), np.zeros((1, 7)))),
     ("set_imu_noise", (np.full((1, 3), -1.0), np.zeros((1, 3)))),
     ("set_imu_noise", (np.zeros((1, 3)), np.full((1, 3), np.nan))),
     ("set_slip_noise", (np.array([-0.1]),)),
     ("set_slip_noise", (np.zeros(2),)),
     ("step", (0.0, np.zeros((1, 2)))),
     ("step", (DT, np.zeros((2, 2)))),
     ("add_robot", (7, math.nan, 0.0, 0.0)),
     ("set_pose", (0, 0.0, math.inf, 0.0))],
)
def test_bad_arguments_raise_value_error(make_swarm, setter, arguments):
    swarm = make_swarm()
    with pytest.raises(ValueError):
        getattr(swarm, setter)(*arguments)


def test_bad_indices_and_lost_bodies(world, make_swarm):
    swarm = make_swarm()
    with pytest.raises(IndexError):
        swarm.set_pose(1, 0.0, 0.0, 0.0)
    with pytest.raises(IndexError):
        swarm.sensor_model(8)
    with pytest.raises(ValueError):
        swarm.add_robot(100, 1.0, 1.0, 0.0)  # handle already used by robot 0
    world.remove(100)
    with pytest.raises(KeyError):
        swarm.step(DT, still(swarm))


HOSTILE = [math.nan, math.inf, -math.inf, 1e308, -1e308, -0.0, 5e-324]


@pytest.mark.parametrize("value", HOSTILE)
def test_hostile_floats_are_refused_or_harmless(world, make_swarm, value):
    add_arena(world, 0.2)
    swarm = make_swarm(ROBOTS[:2])
    n = swarm.size
    attempts = [
        lambda: swarm.step(DT, np.full((n, 2), value)),
        lambda: swarm.step(value, np.zeros((n, 2))),
        lambda: swarm.set_pose(0, value, value, value),
        lambda: swarm.set_odometry(1, value, 0.0, value),
        lambda: swarm.set_ir_noise(np.full((n, 8), value), np.full((n, 8), value),
                                   np.full((n, 8), value)),
        lambda: swarm.set_imu_noise(np.full((n, 3), value), np.full((n, 3), value)),
        lambda: swarm.set_slip_noise(np.full(n, value)),
        lambda: swarm.add_robot(300, value, 0.0, value),  # last: it may change N
    ]
    for attempt in attempts:
        try:
            attempt()
        except ValueError:
            pass
        for _ in range(3):
            swarm.step(DT, np.full((swarm.size, 2), 3.0))
        for name in ("poses", "velocities", "wheel_speeds", "wheel_angles", "odometry",
                     "ranges", "ranges_clean", "detected_points", "detected_normals", "accel",
                     "gyro"):
            assert np.isfinite(getattr(swarm, name)).all(), name


# --- robots added and removed between steps --------------------------------------------------
FAR_APART = [(300 + i, 50.0 * i, 0.0, 0.3 * i) for i in range(3)]     # nobody sees anybody
OUTPUTS = ("poses", "velocities", "wheel_speeds", "wheel_angles", "odometry", "ranges",
           "ranges_clean", "detected_handles", "accel", "gyro")


def all_noise_on(swarm):
    n = swarm.size
    swarm.set_ir_noise(np.ones((n, 8)), np.full((n, 8), -0.01), np.full((n, 8), 0.003))
    swarm.set_imu_noise(np.full((n, 3), 0.05), np.full((n, 3), 0.01))
    swarm.set_slip_noise(np.full(n, 0.05))


def far_apart_run(world, steps_before, steps_after, remove=None, reseed=None):
    """Three robots 50 m apart, each in front of its own wall (so IR noise is drawn); robot
    ``remove`` leaves after ``steps_before`` steps. Returns the swarm."""
    swarm = _core.EpuckSwarm(world, _core.EpuckModel(), 11)
    for i, robot in enumerate(FAR_APART):
        world.add_box(400 + i, (0.005, 0.1, 0.05), (50.0 * i + 0.06, 0.0, 0.05), IDENTITY, GREY)
        swarm.add_robot(*robot)
    all_noise_on(swarm)
    drive = np.random.default_rng(3).uniform(-0.5, 0.5, (steps_before + steps_after, 3, 2))
    for command in drive[:steps_before]:
        swarm.step(DT, command)
    keep = [0, 1, 2]
    if remove is not None:
        swarm.remove_robot(remove)
        keep.remove(remove)
    if reseed is not None:
        swarm.reseed(reseed)
    for command in drive[steps_before:]:
        swarm.step(DT, command[keep])
    return swarm


def test_removing_a_robot_keeps_the_others_noise_streams_bit_for_bit():
    full = far_apart_run(_core.CollisionWorld(), 30, 40)
    removed = far_apart_run(_core.CollisionWorld(), 30, 40, remove=1)
    assert removed.size == 2 and list(removed.handles) == [300, 302]
    assert removed.stream_ids == [0, 2]
    assert not np.array_equal(full.ranges, full.ranges_clean)        # the noise was drawn
    for name in OUTPUTS:
        np.testing.assert_array_equal(getattr(removed, name), getattr(full, name)[[0, 2]],
                                      err_msg=name)


def test_reseed_after_a_removal_restarts_each_robot_on_its_own_stream():
    full = far_apart_run(_core.CollisionWorld(), 10, 25, reseed=4)
    removed = far_apart_run(_core.CollisionWorld(), 10, 25, remove=0, reseed=4)
    for name in OUTPUTS:
        np.testing.assert_array_equal(getattr(removed, name), getattr(full, name)[[1, 2]],
                                      err_msg=name)


def test_remove_robot_takes_its_body_out_and_shifts_the_rows(world, make_swarm):
    swarm = make_swarm(ROBOTS)
    swarm.step(DT, still(swarm))
    poses = swarm.poses
    swarm.remove_robot(2)
    assert not world.has(ROBOTS[2][0]) and world.has(ROBOTS[3][0])
    assert list(swarm.handles) == [r[0] for i, r in enumerate(ROBOTS) if i != 2]
    np.testing.assert_array_equal(swarm.poses, np.delete(poses, 2, axis=0))
    with pytest.raises(ValueError):
        swarm.step(DT, np.zeros((len(ROBOTS), 2)))                 # the old shape
    swarm.step(DT, still(swarm))
    n = swarm.size
    for name, shape in dict(poses=(n, 3), ranges=(n, 8), detected_points=(n, 8, 3),
                            accel=(n, 3), handles=(n,)).items():
        assert getattr(swarm, name).shape == shape, name
    # Nobody detects the removed body any more.
    assert not (swarm.detected_handles == ROBOTS[2][0]).any()


def test_a_robot_added_after_a_removal_gets_a_new_stream_and_can_reuse_nothing(world,
                                                                            make_swarm):
    swarm = make_swarm(ROBOTS[:3])
    swarm.remove_robot(1)
    with pytest.raises(ValueError):
        swarm.add_robot(ROBOTS[0][0], 1.0, 1.0, 0.0)               # still used by robot 0
    assert swarm.add_robot(ROBOTS[1][0], 2.0, 2.0, 0.0) == 2        # its body is free again
    assert swarm.stream_ids == [0, 2, 3]
    swarm.step(DT, still(swarm))
    assert world.has(ROBOTS[1][0])


def test_remove_robot_validates_the_index_and_survives_a_lost_body(world, make_swarm):
    swarm = make_swarm(ROBOTS[:2])
    for bad in (-1, 2):
        with pytest.raises(IndexError):
            swarm.remove_robot(bad)
    world.remove(ROBOTS[0][0])
    swarm.remove_robot(0)              # the swarm lets go of a robot whose body is gone
    swarm.step(DT, still(swarm))
    assert swarm.size == 1
    swarm.remove_robot(0)
    swarm.step(DT, still(swarm))       # an empty swarm still steps
    assert swarm.size == 0 and swarm.poses.shape == (0, 3)


def test_adding_and_removing_is_deterministic():
    def run():
        swarm = arena_swarm(0.25, 21)
        all_noise_on(swarm)
        rng = np.random.default_rng(8)
        for k in range(120):
            if k == 40:
                swarm.remove_robot(3)
            if k == 80:
                swarm.add_robot(900, 0.0, -0.15, 1.0)
                all_noise_on(swarm)
            swarm.step(DT, rng.uniform(-6.0, 6.0, (swarm.size, 2)))
        return swarm

    a, b = run(), run()
    for name in OUTPUTS:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def crowded_world(world):
    """A small arena crowded with every kind of shape: upright and turned boxes, cylinders, a
    sphere and a tilted box (the last two through Bullet's narrowphase)."""
    add_arena(world, 0.3)
    tilt = (math.sin(0.2), 0.0, 0.0, math.cos(0.2))
    world.add_box(20, (0.05, 0.02, 0.03), (0.1, 0.12, 0.03), yaw_quaternion(0.5), GREY)
    world.add_box(21, (0.02, 0.08, 0.03), (-0.15, -0.1, 0.03), IDENTITY, GREY)
    world.add_cylinder(22, 0.03, 0.06, (0.15, -0.15, 0.03), IDENTITY, GREY)
    world.add_sphere(23, 0.025, (-0.1, 0.15, 0.025), IDENTITY, GREY)
    world.add_box(24, (0.03, 0.03, 0.03), (0.0, -0.2, 0.03), tilt, GREY)
    world.add_cylinder(25, 0.01, 0.08, (0.2, 0.05, 0.04), IDENTITY, GREY)
    world.add_box(26, (0.01, 0.01, 0.01), (5.0, 5.0, 0.01), IDENTITY, GREY)  # far away


def crowded_run(touch_every_step, steps=600):
    """Twenty robots with random commands in the crowded world; the readings of every step.
    With @p touch_every_step, a far-away box is set where it is before each step: the world
    has changed, so the swarm keeps nothing (contact lists, what its cones may see) from the
    step before."""
    world = _core.CollisionWorld()
    crowded_world(world)
    swarm = _core.EpuckSwarm(world, _core.EpuckModel(), 11)
    rng = np.random.default_rng(8)
    for i in range(20):
        swarm.add_robot(100 + i, *rng.uniform(-0.25, 0.25, 2), rng.uniform(-3.0, 3.0))
    n = swarm.size
    swarm.set_ir_noise(np.full((n, 8), 0.5), np.full((n, 8), 0.002), np.full((n, 8), 0.001))
    commands = rng.uniform(-4.0, 7.0, (steps // 20, n, 2))
    readings = []
    for step in range(steps):
        if step == 300:  # someone moves an obstacle and a robot between two steps
            world.set_pose(20, (-0.05, 0.05, 0.03), yaw_quaternion(1.0))
            swarm.set_pose(3, 0.0, 0.0, 0.0)
        if touch_every_step:
            world.set_pose(26, (5.0, 5.0, 0.01), IDENTITY)
        swarm.step(DT, commands[step // 20])
        readings.append([swarm.poses, swarm.ranges, swarm.ranges_clean, swarm.detected_handles,
                         swarm.detected_points, swarm.detected_normals, swarm.accel])
    return readings


def test_what_a_step_keeps_for_the_next_changes_no_reading():
    # The contact lists and the cones' candidates last several steps; they may only make a
    # step faster. A world changed before every step rebuilds them every step.
    kept, rebuilt = crowded_run(False), crowded_run(True)
    for step, (a, b) in enumerate(zip(kept, rebuilt)):
        for x, y in zip(a, b):
            assert np.array_equal(x, y), f"step {step}"
    # the run is crowded: robots touch each other, the walls and the obstacles
    handles = np.concatenate([r[3].ravel() for r in kept])
    assert {1, 20, 21, 22, 23, 24, 25}.issubset(set(handles)) and (handles >= 100).any()


def test_revision_counts_changes_of_geometry(world):
    start = world.revision
    world.add_box(1, (0.1, 0.1, 0.1), (0.0, 0.0, 0.1), IDENTITY, GREY)
    world.set_pose(1, (0.1, 0.0, 0.1), IDENTITY)
    world.set_color(1, (0.1, 0.2, 0.3))  # no geometry
    world.remove(1)
    assert world.revision == start + 3

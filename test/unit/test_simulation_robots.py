"""Simulation: robots added and removed between steps (names, placement, rows, handles, noise
streams, commands, components) and static objects removed from the collision world."""
import math
import os

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.epuck.cameras import render_robot_cameras
from epuck_vrep_compat.ros.epuck.profiles import PROFILES
from epuck_vrep_compat.scene.epuck_model import next_robot_number, suffix_number
from epuck_vrep_compat.scene.scene_file import SceneError, load_scene, parse_scene
from repo import REPO

WORLDS = os.path.join(REPO, "worlds")
TEST_WORLDS = os.path.join(REPO, "test", "worlds")
RADIUS_M = 0.037


def arena_sim(n=2, **kwargs):
    return build_simulation(load_scene(os.path.join(WORLDS, "arena.yaml")),
                            SimulationConfig([f"ePuck{i}" for i in range(n)], **kwargs))


def robot_handles(sim, name):
    return sorted(o.handle for o in sim.registry.objects() if o.robot == name)


def test_suffix_numbers_as_vrep():
    assert [suffix_number(n) for n in ("ePuck", "ePuck#0", "ePuck#12", "a#b", "x#", "#3")] == \
        [-1, 0, 12, -1, -1, 3]
    assert next_robot_number(["Floor", "ePuck", "ePuck_base"]) == 1         # -> "#0"
    assert next_robot_number(["ePuck", "ePuck#0", "box#4"]) == 6            # largest anywhere
    assert next_robot_number([]) == 1


def test_an_added_robot_is_named_as_a_vrep_paste_and_placed_free():
    sim = arena_sim()
    epucks = sim.epucks
    before = {o.handle for o in sim.registry.objects()}
    calls = []
    sim.listeners.append(lambda: calls.append(epucks.size))
    parts = epucks.add_robot(near_xy=(0.0, 0.0), yaw_rad=0.4)
    assert calls == [3]
    assert parts.root.name == "ePuck#1" and parts.root.robot == "ePuck2"
    assert sim.registry.handle_of("ePuck_proxSensor7#1") == parts.handle("proxSensor7")
    assert min(robot_handles(sim, "ePuck2")) > max(before)                  # never reused
    assert epucks.robot_names == ["ePuck0", "ePuck1", "ePuck2"]
    assert epucks.robot_index("ePuck2") == 2
    assert epucks.swarm.size == 3 and epucks.command.wheel_rad_s.shape == (3, 2)
    assert len(epucks.start_poses) == 3 and epucks.start_poses[2][2] == pytest.approx(0.4)
    x, y, yaw = epucks.swarm.poses[2]
    assert yaw == pytest.approx(0.4)
    for ox, oy, _ in epucks.swarm.poses[:2]:
        assert math.hypot(x - ox, y - oy) >= 2 * RADIUS_M
    for o in sim.live_obstacles():
        assert math.hypot(x - o.position_m[0], y - o.position_m[1]) > \
            o.footprint_radius_m() + RADIUS_M
    np.testing.assert_allclose(sim.registry.world_pose(parts.root.handle)[0], [x, y, 0.0])
    sim.step()
    assert epucks.swarm.ranges.shape == (3, 8)


def test_a_removed_robot_leaves_everything_and_the_others_keep_handles_and_state():
    sim = arena_sim(3)
    epucks = sim.epucks
    kept = {name: robot_handles(sim, name) for name in ("ePuck0", "ePuck2")}
    gone = robot_handles(sim, "ePuck1")
    epucks.set_wheel_speeds("ePuck2", 1.0, 2.0)
    epucks.set_wheel_speeds("ePuck1", 3.0, 3.0)
    for _ in range(5):
        sim.step()
    pose2 = epucks.swarm.poses[2].copy()
    removed = epucks.remove_robot("ePuck1")
    assert sorted(removed) == gone
    assert not any(h in sim.registry for h in gone) and not sim.world.has(gone[0])
    assert sim.registry.handle_of("ePuck_leftJoint#0") == -1
    assert {n: robot_handles(sim, n) for n in kept} == kept
    assert epucks.robot_names == ["ePuck0", "ePuck2"] and epucks.robot_index("ePuck1") == -1
    assert [p.root.robot for p in epucks.robots] == epucks.robot_names
    assert len(epucks.start_poses) == 2
    np.testing.assert_array_equal(epucks.swarm.poses[1], pose2)
    np.testing.assert_array_equal(epucks.command.wheel_rad_s[1], [1.0, 2.0])
    # The pose source, the wheel joint and the IR cone of ePuck2 read its new row.
    base2 = sim.registry.get(sim.registry.handle_of("ePuck#1"))
    np.testing.assert_allclose(sim.registry.world_pose(base2.handle)[0][:2], pose2[:2])
    sim.step()
    joint = sim.registry.get(sim.registry.handle_of("ePuck_rightJoint#1")).properties["joint"]
    assert joint.velocity() == epucks.swarm.wheel_speeds[1, 1]
    sensor = sim.registry.get(sim.registry.handle_of("ePuck_proxSensor0#1"))
    assert sensor.properties["proximity"].read()[2] == epucks.swarm.detected_handles[1, 0] or \
        epucks.swarm.detected_handles[1, 0] < 0
    joint.set_target_velocity(-0.5)
    assert epucks.command.wheel_rad_s[1, 1] == -0.5
    assert epucks.set_wheel_speeds("ePuck1", 1.0, 1.0)          # a late cmd_vel: ignored
    assert epucks.command.wheel_rad_s.shape == (2, 2)
    sim.reset()
    np.testing.assert_allclose(epucks.swarm.poses[1], epucks.start_poses[1])


def test_the_suffix_follows_the_largest_one_left_in_the_scene():
    sim = arena_sim(3)
    epucks = sim.epucks
    highest = robot_handles(sim, "ePuck2")
    epucks.remove_robot("ePuck2")
    again = epucks.add_robot()
    assert again.root.name == "ePuck#1" and again.root.robot == "ePuck2"     # as V-REP
    assert min(robot_handles(sim, "ePuck2")) > max(highest)                  # new handles
    epucks.remove_robot("ePuck1")
    assert epucks.add_robot().root.name == "ePuck#2"
    assert epucks.robot_names == ["ePuck0", "ePuck2", "ePuck3"]


def test_profile_names_for_added_robots():
    sim = arena_sim(robot_namer=PROFILES["epuck_driver"].robot_name)
    assert sim.epucks.add_robot().root.robot == "epuck_robot_2"


def test_removing_a_robot_does_not_change_the_others_noise():
    """Three robots far apart in an empty arena, every noise source on: the survivors' noisy
    readings are bit for bit those of a run in which nobody was removed, also after a reset
    (which restarts every robot's noise streams)."""
    def run(remove):
        sim = build_simulation(load_scene(os.path.join(TEST_WORLDS, "empty.yaml")),
                               SimulationConfig(["ePuck0", "ePuck1", "ePuck2"], seed=9))
        epucks = sim.epucks
        for k in range(40):
            if k == 15 and remove:
                epucks.remove_robot("ePuck1")
            if k == 25:
                sim.reset()
            for name in epucks.robot_names:
                epucks.set_wheel_speeds(name, 0.3, -0.3)
            sim.step()
        rows = [epucks.robot_index(n) for n in ("ePuck0", "ePuck2")]
        return {k: getattr(epucks.swarm, k)[rows] for k in ("ranges", "accel", "gyro", "poses")}

    removed, full = run(True), run(False)
    assert not np.array_equal(full["ranges"], np.full_like(full["ranges"], 0.05))
    for key in full:
        np.testing.assert_array_equal(removed[key], full[key], err_msg=key)


def test_removing_a_static_object_takes_it_out_of_the_collision_world():
    sim = arena_sim()
    box = sim.registry.handle_of("box0")
    x, y = next(o for o in sim.scene.obstacles if o.name == "box0").position_m
    ray = dict(origins=[[x - 0.2, y, 0.02]], directions=[[1.0, 0.0, 0.0]], max_distance_m=0.4)
    assert sim.world.ray_cast(**ray)[1][0] == box
    calls = []
    sim.listeners.append(lambda: calls.append("changed"))
    assert sim.remove_object(box) == [box]
    assert calls == ["changed"] and box not in sim.registry and not sim.world.has(box)
    assert sim.world.ray_cast(**ray)[1][0] != box
    assert "box0" not in [o.name for o in sim.live_obstacles()]
    sim.step()


def test_a_robot_goes_whole_or_not_at_all():
    sim = arena_sim()
    epucks = sim.epucks
    count = len(sim.registry)
    sensor = sim.registry.handle_of("ePuck_proxSensor3#0")
    with pytest.raises(ValueError, match="remove the robot's base object 'ePuck#0'"):
        sim.remove_object(sensor)
    with pytest.raises(KeyError):
        sim.remove_object(99999)
    assert len(sim.registry) == count and epucks.size == 2
    assert sorted(sim.remove_object(sim.registry.handle_of("ePuck#0"))) == \
        sorted(set(range(1, count + 1)) - {o.handle for o in sim.registry.objects()})
    assert epucks.robot_names == ["ePuck0"]


def test_a_full_arena_refuses_a_robot_and_changes_nothing():
    scene = parse_scene({"arena": {"size_m": [0.2, 0.2]}, "robots": [{"position_m": [0, 0]}]})
    sim = build_simulation(scene, SimulationConfig(["ePuck0"]))
    epucks = sim.epucks
    count = len(sim.registry)
    with pytest.raises(SceneError, match="no free place"):
        epucks.add_robot()
    assert len(sim.registry) == count and epucks.size == 1 and epucks.swarm.size == 1
    epucks.remove_robot("ePuck0")
    assert epucks.size == 0 and epucks.swarm.poses.shape == (0, 3)
    sim.step()                                              # an empty scene still steps
    assert epucks.add_robot().root.name == "ePuck#0"


def test_cameras_rendered_together_equal_each_camera_rendered_alone():
    sim = arena_sim(6)
    epucks = sim.epucks
    for k, name in enumerate(epucks.robot_names):
        epucks.set_wheel_speeds(name, 2.0 + k, 4.0 - k)         # each robot turns its own way
    for _ in range(30):
        sim.step()
    epucks.remove_robot("ePuck2")                               # rows shift: names still find them
    epucks.add_robot((0.2, -0.2), 1.0)
    names = epucks.robot_names[::-1]
    images = render_robot_cameras(epucks, names, threads=2)
    assert images.shape == (len(names), epucks.camera.height, epucks.camera.width, 3)
    for name, image in zip(names, images):
        parts = epucks.robots[epucks.robot_index(name)]
        rgb, _depth = parts.parts["camera"].properties["vision"].render()
        assert np.array_equal(image, rgb), name
    assert render_robot_cameras(epucks, []).shape == (0, epucks.camera.height,
                                                      epucks.camera.width, 3)

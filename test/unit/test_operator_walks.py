"""The operator's motions: seeded random walks (deterministic per seed, speeds in range, on the
floor, approaching every robot), recorded traces (interpolation, the shorter arc, held at the
ends) and the scene file's checks of both. Pure logic: no ROS, no pybullet."""
import math
import os

import numpy as np
import pytest

from epuck_vrep_compat.cell.devices.operator import operator_motion
from epuck_vrep_compat.cell.devices.operator_motion import TimedPath
from epuck_vrep_compat.cell.devices.operator_walk import Floor, generate_walk
from epuck_vrep_compat.scene.operator_file import (
    WalkSpec, check_on_floor, override_motion, parse_operator, read_trace)
from epuck_vrep_compat.scene.validation import SceneError
from repo import REPO

ARENA = (6.0, 5.0)                    # worlds/merlin_safety.yaml's
ROBOTS = [("IRB140", 0.4, 1.9), ("SIX", 2.1, -1.2), ("youBot", -1.9, -0.6)]
FLOOR = Floor.of_arena(ARENA, 0.2)


def _walk(seed, **kw):
    return generate_walk(WalkSpec(seed, **kw), FLOOR, ROBOTS)


def _sampled(path, dt=0.05):
    times = np.arange(0.0, path.duration_s + 1.0, dt)
    return times, np.array([path.at(t)[:3] for t in times])


def test_a_walk_is_its_seeds_alone():
    a, legs_a = _walk(7)
    b, legs_b = _walk(7)
    c, _ = _walk(8)
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_array_equal(a.xy, b.xy)
    np.testing.assert_array_equal(a.heading, b.heading)
    assert legs_a == legs_b
    assert not np.array_equal(a.xy, c.xy)
    # drawing from numpy's global generator or any other changes nothing
    np.random.seed(123)
    np.random.default_rng(5).random(100)
    np.testing.assert_array_equal(_walk(7)[0].xy, a.xy)


@pytest.mark.parametrize("seed", range(20))
def test_speeds_pauses_and_the_floor_hold(seed):
    path, legs = _walk(seed, speed_m_s=(0.3, 2.0), pause_s=(0.0, 2.0), legs=20)
    assert len(legs) == 20
    assert all(0.3 <= leg.speed_m_s <= 2.0 and 0.0 <= leg.pause_s <= 2.0 for leg in legs)
    times, poses = _sampled(path)
    assert FLOOR.contains(poses[:, 0], poses[:, 1])
    speeds = np.hypot(*np.diff(poses[:, :2], axis=0).T) / np.diff(times)
    assert speeds.max() <= 2.0 + 1e-9
    # each leg takes its length at its speed
    ends = path.xy[1::2]
    assert np.allclose(ends[:20], [leg.goal for leg in legs])
    assert path.duration_s > 0.0 and path.at(path.duration_s + 10.0)[:2] == tuple(ends[19])


def test_every_robot_is_approached_and_approaches_end_near_its_base():
    _, legs = _walk(3, approach_probability=0.5, legs=20, approach_distance_m=(0.5, 1.0))
    approached = [leg for leg in legs if leg.approaches]
    assert {leg.approaches for leg in approached} == {r[0] for r in ROBOTS}
    bases = {name: (x, y) for name, x, y in ROBOTS}
    for leg in approached:
        d = math.dist(leg.goal, bases[leg.approaches])
        assert d <= 1.0 + 1e-9          # a goal pulled inside the floor only comes nearer
    _, none = _walk(3, approach_probability=0.0)
    _, every = _walk(3, approach_probability=1.0, legs=9)
    assert not any(leg.approaches for leg in none)
    assert all(leg.approaches for leg in every)
    assert sorted(leg.approaches for leg in every) == sorted([r[0] for r in ROBOTS] * 3)


def test_he_faces_where_he_walks_and_turns_while_he_stands():
    path, legs = _walk(11, pause_s=(1.0, 2.0))
    x0, y0, h0, moving = path.at(0.5 * path.t[1])
    gx, gy = legs[0].goal
    assert moving and h0 == pytest.approx(math.atan2(gy - y0, gx - x0))
    arrive, depart = path.t[1], path.t[2]
    assert depart - arrive == pytest.approx(legs[0].pause_s)
    standing = path.at(0.5 * (arrive + depart))
    assert standing[:2] == pytest.approx((gx, gy)) and not standing[3]


def test_a_timed_path_interpolates_on_the_shorter_arc_and_holds_its_ends():
    path = TimedPath([1.0, 2.0, 4.0], [0.0, 1.0, 1.0], [0.0, 0.0, 2.0],
                     [3.0, -3.0, 0.0])
    assert path.at(0.0) == (0.0, 0.0, pytest.approx(3.0), False)      # held before the start
    x, y, h, _ = path.at(1.5)
    assert (x, y) == (0.5, 0.0)
    # from 3 to -3 rad the shorter way is through pi (0.28 rad), not through 0 (6 rad)
    assert abs(h) == pytest.approx(math.pi, abs=0.01)
    assert path.at(3.0)[:2] == (1.0, 1.0)
    assert path.at(4.0)[:3] == (1.0, 2.0, 0.0)
    assert path.at(100.0)[:3] == (1.0, 2.0, 0.0)                       # held after the end
    jump = TimedPath([0.0, 1.0, 1.0, 2.0], [0, 1, 5, 5], [0, 0, 0, 0], [0, 0, 0, 0])
    assert jump.at(1.0)[0] == 5.0          # two keyframes at one time: the later holds


def test_a_timed_paths_heading_is_in_the_joints_range():
    """(-pi, pi], as V-REP reports angles and the cell's cyclic joints do (one wrap for both):
    a heading of -pi is pi, moving or held."""
    path = TimedPath([0.0, 1.0], [0.0, 1.0], [0.0, 0.0], [-math.pi, -math.pi])
    assert path.at(0.0)[2] == math.pi
    assert path.at(0.5)[2] == math.pi
    assert path.at(5.0)[2] == math.pi


def _csv(tmp_path, text, name="walk.csv"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_a_trace_is_replayed_exactly_at_its_rows(tmp_path):
    rows = [(0.0, -1.0, 0.5, 0.0), (0.4, -0.6, 0.55, 0.1), (1.3, 0.2, 0.9, 0.7),
            (2.0, 0.25, 1.2, 1.5)]
    path = _csv(tmp_path, "t,x,y,heading\n" + "".join(f"{t},{x},{y},{h}\n"
                                                     for t, x, y, h in rows))
    spec = parse_operator({"name": "Bill", "trace": "walk.csv"}, "cell.operator",
                          str(tmp_path))
    assert spec.trace.path == path and spec.walk is None and not spec.waypoints_m
    motion, legs = operator_motion(spec, ARENA, ROBOTS)
    assert legs is None
    for t, x, y, h in rows:
        assert motion.at(t)[:3] == (x, y, h)
    assert motion.at(0.2)[:3] == pytest.approx((-0.8, 0.525, 0.05))
    assert motion.at(50.0)[:3] == rows[-1][1:]


@pytest.mark.parametrize("text, problem", [
    ("", "row 1: the header must be 't,x,y,heading'"),
    ("time,x,y,yaw\n0,0,0,0\n", "row 1: the header must be"),
    ("t,x,y,heading\n", "no rows after the header"),
    ("t,x,y,heading\n0,0,0,0\n1,0,0\n", "row 3: expected 4 values"),
    ("t,x,y,heading\n0,0,0,0\n1,a,0,0\n", "row 3: x is not a number: 'a'"),
    ("t,x,y,heading\n0,0,0,0\n1,0,nan,0\n", "row 3: y is not finite"),
    ("t,x,y,heading\n0,0,0,0\n0.5,0,0,0\n0.5,1,0,0\n", "row 4: t must increase"),
    ("t,x,y,heading\n-1,0,0,0\n", "row 2: t must start at >= 0"),
])
def test_a_bad_trace_is_named_by_file_row_and_problem(tmp_path, text, problem):
    path = _csv(tmp_path, text)
    with pytest.raises(SceneError) as e:
        read_trace(path)
    assert path in str(e.value) and problem in str(e.value)


def test_a_trace_outside_the_cell_or_missing_is_refused(tmp_path):
    _csv(tmp_path, "t,x,y,heading\n0,0,0,0\n1,0,0,0\n\n2,2500,0,0\n", "mm.csv")
    spec = parse_operator({"name": "Bill", "trace": "mm.csv"}, "cell.operator", str(tmp_path))
    with pytest.raises(SceneError, match=r"mm.csv' row 5: \(2500, 0\) is outside the cell's "
                       r"floor \[-3, 3\] x \[-2.5, 2.5\] m"):
        check_on_floor(spec, ARENA)
    missing = os.path.join(str(tmp_path), "none.csv")
    with pytest.raises(SceneError, match=f"'{missing}': cannot read it"):
        parse_operator({"name": "Bill", "trace": "none.csv"}, "cell.operator", str(tmp_path))


@pytest.mark.parametrize("d, problem", [
    ({}, r"needs exactly one of \['waypoints_m', 'walk', 'trace'\]"),
    ({"walk": {"seed": 1}, "trace": "a.csv"}, "needs exactly one of"),
    ({"walk": {"seed": 1}, "speed_m_s": 1.0}, "speed_m_s goes with waypoints_m"),
    ({"walk": {}}, r"walk.seed is required"),
    ({"walk": {"seed": -1}}, "walk.seed must be a non-negative integer"),
    ({"walk": {"seed": 1.5}}, "walk.seed must be a non-negative integer"),
    ({"walk": {"seed": 1, "speed_m_s": [2.0, 0.3]}}, r"walk.speed_m_s must be \[lo, hi\]"),
    ({"walk": {"seed": 1, "speed_m_s": [0.0, 1.0]}}, r"walk.speed_m_s must be \[lo, hi\]"),
    ({"walk": {"seed": 1, "pause_s": [-1.0, 1.0]}}, r"walk.pause_s must be \[lo, hi\]"),
    ({"walk": {"seed": 1, "approach_probability": 1.5}}, "approach_probability must be in"),
    ({"walk": {"seed": 1, "legs": 0}}, "walk.legs must be an integer"),
    ({"walk": {"seed": 1, "stride": 2}}, r"walk: unknown key\(s\) \['stride'\]"),
    ({"walk": 3}, "walk must be a mapping"),
    ({"trace": 3}, "trace must name a CSV file"),
    ({"waypoints_m": [[0, 0], [0, 0]]}, r"waypoints_m\[1\] repeats the point before it"),
])
def test_a_bad_operator_motion_is_named(d, problem):
    with pytest.raises(SceneError, match=problem):
        parse_operator({"name": "Bill", **d}, "cell.operator", "/")


def test_a_walks_defaults_are_the_standards_speeds():
    spec = parse_operator({"name": "Bill", "walk": {"seed": 4}}, "cell.operator", "/")
    assert spec.walk == WalkSpec(4, (0.3, 2.0), (0.0, 2.0), 0.5, 20, (0.5, 1.0))


def test_a_launch_overrides_the_scenes_motion(tmp_path):
    _csv(tmp_path, "t,x,y,heading\n0,1,1,0\n", "one.csv")
    scene = parse_operator({"name": "Bill", "waypoints_m": [[0, 0], [1, 0]], "color": [1, 0, 0]},
                           "cell.operator", "/")
    assert override_motion(scene) is scene
    walk = override_motion(scene, walk_seed=9)
    assert walk.walk == WalkSpec(9) and not walk.waypoints_m and walk.color == (1, 0, 0)
    tuned = parse_operator({"name": "Bill", "walk": {"seed": 1, "legs": 3}}, "cell.operator", "/")
    assert override_motion(tuned, walk_seed=2).walk == WalkSpec(2, legs=3)
    traced = override_motion(tuned, trace="one.csv", base_dir=str(tmp_path))
    assert traced.walk is None and traced.trace.x_m.tolist() == [1.0]
    with pytest.raises(SceneError, match="not both"):
        override_motion(scene, walk_seed=1, trace="one.csv")
    with pytest.raises(SceneError, match="walk seed must be a non-negative integer"):
        override_motion(scene, walk_seed=-3)


def _cell_sim(seed, walk_seed, trace=None):
    from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
    from epuck_vrep_compat.scene.scene_file import load_scene
    scene = load_scene(os.path.join(REPO, "worlds", "merlin_safety.yaml"))
    scene.cell.operator = override_motion(scene.cell.operator, walk_seed, trace)
    return build_simulation(scene, SimulationConfig(seed=seed))


def test_in_the_simulation_his_pose_is_the_walks_at_the_simulated_time():
    runs = []
    for seed in (0, 99):                       # the simulation's seed leaves the walk alone
        sim = _cell_sim(seed, walk_seed=5)
        poses = []
        for _ in range(60):
            sim.step()
            poses.append(sim.cell.operator.state())
        assert poses[-1] == sim.cell.operator.path.at(sim.time_s)
        sim.reset()                            # the walk starts again with the reset
        assert sim.cell.operator.state() == sim.cell.operator.path.at(0.0)
        sim.step()
        assert sim.cell.operator.state() == poses[0]
        sim.cell.close()
        runs.append(poses)
    assert runs[0] == runs[1]
    assert len(sim.cell.operator.legs) == 20 and sim.cell.operator.path.duration_s > 10.0


def test_his_motion_is_described_in_a_line(tmp_path):
    sim = _cell_sim(0, walk_seed=5)
    line = sim.cell.operator.describe()
    sim.cell.close()
    assert line.startswith("Bill walks seed 5: 20 legs in ") and "IRB140" in line
    sim = _cell_sim(0, walk_seed=None)
    assert sim.cell.operator.describe() == "Bill walks 2 waypoints at 1.6 m/s, out and back"
    sim.cell.close()

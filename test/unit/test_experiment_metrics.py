"""The experiment metrics on synthetic recordings with answers known by hand: a square path's
length, a drive into a wall, two robots meeting, a region reached, a swept row of cells, IR
and IMU readings of known statistics; the recording file's round trip bit for bit; and every
malformed metric option refused by name."""
import math
import os

import numpy as np
import pytest
import yaml

from epuck_vrep_compat.experiment import metrics_geometry as geo
from epuck_vrep_compat.experiment.metrics import (
    RunContext, TopicSeries, columns, compute, load_recording, robots_in, save_recording,
    topics_needed, validate_metric)
from repo import REPO

X, Y = "pose.pose.position.x", "pose.pose.position.y"
WALL_X_M = 0.5                        # the default 1 m arena's +x wall, inner face


def odom(t, x, y):
    t = np.asarray(t, dtype=float)
    return TopicSeries("nav_msgs/Odometry", t, {X: np.broadcast_to(x, t.shape),
                                                  Y: np.broadcast_to(y, t.shape)})


def ctx_of(tracks, world=None, **topics):
    """A run of robots ``{name: (t, x, y)}`` plus other topics."""
    rec = {f"/{name}/ground_truth": odom(*track) for name, track in tracks.items()}
    rec.update({"/" + k.replace("__", "/"): v for k, v in topics.items()})
    return RunContext(rec, world=world or {})


def one(spec, ctx, warnings=None):
    return compute([spec], ctx, warnings=warnings)


def square_path(side_m, samples_per_side=50):
    corners = np.array([[0, 0], [side_m, 0], [side_m, side_m], [0, side_m], [0, 0]])
    s = np.linspace(0.0, 1.0, samples_per_side, endpoint=False)[:, None]
    xy = np.concatenate([a + s * (b - a) for a, b in zip(corners[:-1], corners[1:])] +
                        [corners[-1:]])
    return np.arange(len(xy)) * 0.05, xy[:, 0], xy[:, 1]


def test_distance_driven_is_the_mean_path_length_of_the_robots():
    t, x, y = square_path(0.2)
    straight = (t, np.linspace(-0.3, 0.1, t.size), np.zeros(t.size))
    ctx = ctx_of({"ePuck0": (t, x, y), "ePuck1": straight})
    assert one({"metric": "distance_driven", "robots": ["ePuck0"]}, ctx)[
        "distance_driven_m"] == pytest.approx(0.8, abs=1e-12)
    assert one({"metric": "distance_driven"}, ctx)["distance_driven_m"] == \
        pytest.approx(0.6, abs=1e-12)


def test_a_drive_into_the_wall_is_one_onset_and_its_contact_time():
    # 0.1 m/s along +x until the disk is 0.5 mm from the wall; within the 2 mm margin from
    # x >= 0.461, i.e. from the sample at t = 4.61 s to the end at 10 s
    t = np.round(np.arange(0, 1001) * 0.01, 10)
    x = np.minimum(0.0005 + 0.1 * t, WALL_X_M - geo.EPUCK_RADIUS_M - 0.0005)
    row = one({"metric": "collisions"}, ctx_of({"ePuck0": (t, x, 0.0)}))
    assert row == pytest.approx({"collisions": 1, "collisions_wall": 1, "collisions_obstacle": 0,
                                 "collisions_robot": 0, "time_in_contact_s": 10.0 - 4.61})


def test_leaving_and_touching_again_is_a_second_onset():
    t = np.arange(0, 300) * 0.1
    gap = np.where(((t >= 5) & (t < 10)) | (t >= 20), 0.001, 0.05)   # away, touch, away, touch
    row = one({"metric": "collisions"}, ctx_of({"ePuck0": (t, WALL_X_M - 0.037 - gap, 0.0)}))
    assert row["collisions_wall"] == 2
    assert row["time_in_contact_s"] == pytest.approx(5.0 + 9.9)   # the last sample adds none
    assert geo.onsets([True, True, False, True]) == 1    # touching from the start: no onset


def test_obstacles_of_the_arena_file_are_hit_with_their_shapes():
    with open(os.path.join(REPO, "worlds", "arena.yaml"), encoding="utf-8") as f:
        world = yaml.safe_load(f)
    shapes = geo.shapes_of(world)
    # box0: 0.12 x 0.06 at (0.28, 0.28), yaw 0.5; points off the middle of its +x face
    direction = np.array([math.cos(0.5), math.sin(0.5)])
    points = np.array([0.28, 0.28]) + np.outer([0.06 + 0.037 + 0.001, 0.06 + 0.037 + 0.003],
                                               direction)
    wall, obstacle = geo.clearances(shapes, points)
    assert obstacle == pytest.approx([0.001, 0.003], abs=1e-12)
    assert wall.min() > 0.05
    # cylinder0 (r 0.04 at (0.25, -0.30)) approached from -x at 0.1 m/s, stopping 1 mm away
    t = np.round(np.arange(0, 301) * 0.01, 10)
    x = np.minimum(-0.0005 + 0.1 * t, 0.25 - 0.04 - 0.037 - 0.001)
    row = one({"metric": "collisions"}, ctx_of({"ePuck0": (t, x, -0.30)}, world))
    assert (row["collisions_obstacle"], row["collisions_wall"]) == (1, 0)
    assert row["time_in_contact_s"] == pytest.approx(3.0 - 1.72)


def test_missing_obstacle_keys_take_the_scene_files_defaults():
    world = {"arena": {"size_m": [2.0, 1.0]},
             "obstacles": [{"shape": "box", "position_m": [0.0, 0.0]},
                           {"shape": "cylinder", "position_m": [0.5, 0.0]}]}
    wall, obstacle = geo.clearances(geo.shapes_of(world), [[0.0, 0.2], [0.5, 0.2], [0.9, 0.0]])
    assert obstacle[:2] == pytest.approx([0.2 - 0.05 - 0.037, 0.2 - 0.03 - 0.037])
    assert wall[2] == pytest.approx(1.0 - 0.9 - 0.037)


def test_two_robots_meeting_give_their_separation_and_one_robot_collision():
    # closing at 0.1 m/s from 0.6 m apart, stopping 0.075 m apart (1 mm between the disks);
    # within the margin from the sample at t = 5.3 s: both robots in contact until 10 s
    t = np.round(np.arange(0, 101) * 0.1, 10)
    ctx = ctx_of({"ePuck0": (t, np.minimum(-0.3 + 0.05 * t, -0.0375), 0.0),
                  "ePuck1": (t, np.maximum(0.3 - 0.05 * t, 0.0375), 0.0)})
    row = compute([{"metric": "min_separation"}, {"metric": "collisions"}], ctx)
    assert row["min_separation_m"] == pytest.approx(0.075, abs=1e-12)
    assert (row["collisions"], row["collisions_robot"], row["collisions_wall"]) == (1, 1, 0)
    assert row["time_in_contact_s"] == pytest.approx(2 * (10.0 - 5.3))


def test_separation_uses_the_instants_common_to_both_robots():
    t = np.arange(0, 11) * 1.0
    dense = np.round(np.arange(0, 101) * 0.1, 10)
    ax = 0.2 + 0.01 * (dense - 5.0) ** 2
    ax[51] = 0.1                      # closer, but at 5.1 s, which is no stamp of b
    ctx = ctx_of({"a": (dense, ax, 0.0), "b": (t, 0.0, 0.0)})
    assert one({"metric": "min_separation"}, ctx)["min_separation_m"] == pytest.approx(0.2)


def test_one_robot_has_no_separation():
    warnings = []
    row = one({"metric": "min_separation"}, ctx_of({"ePuck0": ([0, 1], 0.0, 0.0)}), warnings)
    assert math.isnan(row["min_separation_m"]) and warnings == []


@pytest.mark.parametrize("region", [{"center_m": [0.3, 0.0], "radius_m": 0.055},
                                    {"min_m": [0.245, -0.1], "max_m": [0.4, 0.1]}])
def test_time_to_region_of_any_and_of_all_robots(region):
    # x >= 0.245 from 2.45 s (first sample 2.5 s) for the fast robot, 6.125 s (6.2 s) the slow
    t = np.round(np.arange(0, 101) * 0.1, 10)
    tracks = {"fast": (t, 0.1 * t, 0.0), "slow": (t, 0.04 * t, 0.0), "still": (t, 0.0, 0.0)}
    ctx = ctx_of(tracks)
    spec = {"metric": "time_to_region", "region": region, "robots": ["fast", "slow"]}
    assert one(spec, ctx)["time_to_region_s"] == pytest.approx(2.5)
    assert one(dict(spec, all=True), ctx)["time_to_region_s"] == pytest.approx(6.2)
    assert math.isnan(one(dict(spec, all=True, robots=["fast", "still"]), ctx)[
        "time_to_region_s"])
    assert math.isnan(one(dict(spec, robots=["still"]), ctx)["time_to_region_s"])


@pytest.mark.parametrize("y, cell_m, size_m, expected", [
    (0.05, 0.1, 1.0, 10 / 100),       # along a row of centres: that row only
    (0.0, 0.05, 1.0, 40 / 400),       # between two rows 0.025 m away: both rows
    (0.1, 0.1, 1.0, 0.0),             # 0.05 m from the centres on both sides: none
    (0.049, 0.05, 2.0, 80 / 800),     # the row above too (0.026 m); a 2 m x 1 m arena
])
def test_coverage_of_a_swept_row(y, cell_m, size_m, expected):
    x = np.linspace(-0.5 * size_m + 0.05, 0.5 * size_m - 0.05, 1000)
    ctx = ctx_of({"ePuck0": (np.arange(x.size) * 0.1, x, y)},
                 {"arena": {"size_m": [size_m, 1.0]}})
    assert one({"metric": "coverage", "cell_m": cell_m}, ctx)["coverage"] == \
        pytest.approx(expected)


def test_coverage_counts_each_cell_once_across_robots():
    t = np.arange(0, 91) * 0.1
    same = (t, -0.45 + 0.1 * t, 0.05)
    ctx = ctx_of({"a": same, "b": same, "c": (t, -0.45 + 0.1 * t, -0.05)})
    assert one({"metric": "coverage", "cell_m": 0.1}, ctx)["coverage"] == pytest.approx(0.2)


def range_series(readings, max_range=0.05):
    t = np.arange(len(readings)) * 0.1
    return TopicSeries("sensor_msgs/Range", t, {"range": readings, "max_range": np.full(
        len(readings), max_range), "min_range": np.full(len(readings), 0.0015)})


def test_ir_stats_wrong_fraction_mean_and_sd():
    # 25 wrong readings of 0.03 m among 100; one 0.5 µm short of max range is not wrong
    readings = np.array([0.03] * 25 + [0.05] * 74 + [0.05 - 5e-7])
    ctx = ctx_of({"ePuck0": ([0.0], 0.0, 0.0)}, ePuck0__proximity3=range_series(readings))
    row = one({"metric": "ir_stats", "sensor": 3}, ctx)
    assert row["ir3_wrong_fraction"] == pytest.approx(0.25)
    assert row["ir3_mean_m"] == pytest.approx(readings.mean())
    assert row["ir3_sd_m"] == pytest.approx(np.std(readings, ddof=1))
    windowed = one({"metric": "ir_stats", "sensor": 3, "window_s": [2.0, 4.0]}, ctx)
    assert windowed["ir3_wrong_fraction"] == pytest.approx(5 / 21)    # samples 20..40


def imu_series(x, z):
    t = np.arange(len(x)) * 0.02
    zeros = np.zeros(len(x))
    return TopicSeries("sensor_msgs/Imu", t, {"linear_acceleration.x": x,
                                              "linear_acceleration.y": zeros,
                                              "linear_acceleration.z": z,
                                              "angular_velocity.z": zeros})


@pytest.mark.parametrize("topic", ["imu", "accel"])
def test_imu_stats_mean_and_sd_in_the_window(topic):
    x = np.array([5.0] * 10 + [0.1, 0.3] * 50)     # the first 0.2 s are excluded
    z = np.full(x.size, 9.81)
    ctx = ctx_of({"ePuck0": ([0.0], 0.0, 0.0)}, **{f"ePuck0__{topic}": imu_series(x, z)})
    row = one({"metric": "imu_stats", "robot": "ePuck0", "window_s": [0.19, 100.0]}, ctx)
    assert row["accel_x_mean"] == pytest.approx(0.2)
    assert row["accel_x_sd"] == pytest.approx(math.sqrt(0.01 * 100 / 99))
    assert (row["accel_y_mean"], row["accel_y_sd"]) == (0.0, 0.0)
    assert row["accel_z_mean"] == pytest.approx(9.81) and row["accel_z_sd"] == pytest.approx(0)


@pytest.mark.parametrize("stat, expected", [
    ("mean", 2.5), ("sd", np.std([1, 2, 3, 4], ddof=1)), ("min", 1.0), ("max", 4.0),
    ("last", 4.0), ("count", 4.0), ("rate_hz", 3 / 1.5)])
def test_topic_stat(stat, expected):
    ctx = RunContext({"/level": TopicSeries("std_msgs/Float64", [0.0, 0.5, 1.0, 1.5],
                                            {"data": [1.0, 2.0, 3.0, 4.0]})})
    spec = {"metric": "topic_stat", "topic": "/level", "field": "data", "stat": stat,
            "name": "level"}
    assert one(spec, ctx) == {"level": pytest.approx(expected)}


def test_missing_data_gives_nan_columns_and_a_warning(caplog):
    ctx = ctx_of({"ePuck0": ([0.0, 1.0], 0.0, 0.0)})
    specs = [{"metric": "imu_stats"}, {"metric": "distance_driven"}]
    warnings = []
    row = compute(specs, ctx, warnings=warnings)
    assert all(math.isnan(row[f"accel_{a}_{s}"]) for a in "xyz" for s in ("mean", "sd"))
    assert row["distance_driven_m"] == 0.0
    assert len(warnings) == 1 and "/ePuck0/imu" in warnings[0]
    compute(specs, ctx)
    assert "/ePuck0/imu" in caplog.text
    assert math.isnan(one({"metric": "coverage"}, RunContext({}), [])["coverage"])


def test_user_metrics_numbers_mappings_and_failures():
    ctx = ctx_of({"ePuck0": ([0.0, 1.0], 0.0, 0.0)})

    def broken(_ctx):
        raise ZeroDivisionError("oops")

    custom = {"score": lambda c: len(c.robots),
              "pair": lambda c: {"a": c.series("/ePuck0/ground_truth").t.size - 1, "b": 2.5},
              "broken": broken}
    warnings = []
    row = compute([{"metric": "score"}, {"metric": "pair", "custom": True, "prefix": "p."},
                   {"metric": "broken", "custom": True}, {"metric": "absent", "custom": True}],
                  ctx, custom, warnings)
    assert row["score"] == 1.0 and (row["p.a"], row["p.b"]) == (1.0, 2.5)
    assert math.isnan(row["broken"]) and math.isnan(row["absent"])
    assert [w.split(":")[0] for w in warnings] == ["metric broken", "metric absent"]


def test_columns_clash_unless_prefixed_and_topics_to_record():
    imu0 = {"metric": "imu_stats", "robot": "ePuck0"}
    with pytest.raises(ValueError, match="accel_x_mean"):
        columns([imu0, {"metric": "imu_stats", "robot": "ePuck1"}])
    assert columns([imu0, {"metric": "imu_stats", "robot": "ePuck1", "prefix": "e1_"}])[6] == \
        "e1_accel_x_mean"
    assert topics_needed([{"metric": "collisions"}, imu0, {"metric": "ir_stats", "sensor": 2},
                          {"metric": "mine", "custom": True, "topics": ["/ePuck0/cmd_vel"]},
                          {"metric": "topic_stat", "topic": "/x", "stat": "count",
                           "name": "n"}]) == [
        "/*/ground_truth", "/*/proximity2", "/ePuck0/accel", "/ePuck0/cmd_vel",
        "/ePuck0/imu", "/x"]


def test_recording_round_trip_is_bit_identical(tmp_path):
    rng = np.random.default_rng(7)
    t = np.sort(rng.uniform(0, 10, 50))
    values = rng.normal(size=50)
    values[:4] = [np.nan, np.inf, -0.0, 5e-324]
    rec = {"/ePuck0/ground_truth": TopicSeries("nav_msgs/Odometry", t, {X: values, Y: -t}),
           "/team_a/epuck_1/proximity0": TopicSeries("sensor_msgs/Range", [], {"range": []})}
    path = str(tmp_path / "run.rec")
    save_recording(path, rec)
    back = load_recording(path)
    assert list(back) == sorted(rec)
    for topic, s in rec.items():
        assert back[topic].type == s.type and list(back[topic].fields) == list(s.fields)
        for a, b in [(s.t, back[topic].t)] + [(v, back[topic].fields[k])
                                              for k, v in s.fields.items()]:
            assert a.dtype == b.dtype == np.float64 and a.tobytes() == b.tobytes()
    np.savez(str(tmp_path / "other.npz"), a=np.zeros(1))
    with pytest.raises(ValueError, match="not a recording"):
        load_recording(str(tmp_path / "other.npz"))


def test_series_checks_and_names_its_fields():
    s = TopicSeries("sensor_msgs/Range", [0.0, 1.0], {"range": [0.1, 0.2]})
    with pytest.raises(KeyError, match="range"):
        s.field("ranges")
    with pytest.raises(ValueError, match="3 stamps"):
        TopicSeries("x/Y", [0.0, 1.0, 2.0], {"data": [1.0]})
    with pytest.raises(ValueError, match="sorted"):
        TopicSeries("x/Y", [1.0, 0.0], {})


def test_robots_come_from_the_ground_truth_topics():
    rec = {"/ePuck1/ground_truth": odom([0], 0, 0), "/team_a/epuck_1/ground_truth":
           odom([0], 0, 0), "/ePuck0/imu": imu_series([0.0], [9.81]), "/ground_truth":
           odom([0], 0, 0)}
    assert robots_in(rec) == ["ePuck1", "team_a/epuck_1"]
    assert RunContext(rec).robots == ["ePuck1", "team_a/epuck_1"]
    assert RunContext(rec, robots=["ePuck1"]).robots == ["ePuck1"]


@pytest.mark.parametrize("spec, named", [
    ({"metric": "nope"}, "'nope'"),
    ({"metrics": "coverage"}, "'metric'"),
    ({"metric": "collisions", "margin_m": -0.001}, "'margin_m'"),
    ({"metric": "collisions", "margin_m": "2mm"}, "'margin_m'"),
    ({"metric": "coverage", "cell_m": 0}, "'cell_m'"),
    ({"metric": "coverage", "cell": 0.1}, "'cell'"),
    ({"metric": "distance_driven", "robots": "ePuck0"}, "'robots'"),
    ({"metric": "distance_driven", "robots": ["ePuck0", 3]}, "'robots'"),
    ({"metric": "distance_driven", "prefix": "a b"}, "'prefix'"),
    ({"metric": "time_to_region"}, "'region'"),
    ({"metric": "time_to_region", "region": {"center_m": [0, 0]}}, "'region'"),
    ({"metric": "time_to_region", "region": {"center_m": [0, 0], "radius_m": -1}}, "'region'"),
    ({"metric": "time_to_region", "region": {"min_m": [0, 0], "max_m": [0, 1]}}, "'region'"),
    ({"metric": "time_to_region", "region": {"center_m": [0, 0], "radius_m": 1}, "all": 1},
     "'all'"),
    ({"metric": "imu_stats", "window_s": [2, 1]}, "'window_s'"),
    ({"metric": "imu_stats", "robot": ""}, "'robot'"),
    ({"metric": "ir_stats"}, "'sensor'"),
    ({"metric": "ir_stats", "sensor": 8}, "'sensor'"),
    ({"metric": "ir_stats", "sensor": True}, "'sensor'"),
    ({"metric": "topic_stat", "topic": "x", "stat": "count", "name": "n"}, "'topic'"),
    ({"metric": "topic_stat", "topic": "/x", "stat": "median", "name": "n"}, "'stat'"),
    ({"metric": "topic_stat", "topic": "/x", "stat": "count", "name": "1n"}, "'name'"),
    ({"metric": "topic_stat", "topic": "/x", "stat": "count"}, "'name'"),
    ({"metric": "mine", "custom": True, "topics": "/x"}, "'topics'"),
    ({"metric": "distance_driven", "custom": True}, "'distance_driven'"),
])
def test_each_bad_option_is_refused_by_name(spec, named):
    with pytest.raises(ValueError, match=named):
        validate_metric(spec)


def test_good_specs_pass():
    for spec in [{"metric": "collisions", "margin_m": 0}, {"metric": "coverage", "cell_m": 0.02},
                 {"metric": "ir_stats", "sensor": 0, "robot": "/ePuck2/", "window_s": [0, 5]},
                 {"metric": "time_to_region", "all": True,
                  "region": {"min_m": [0, 0], "max_m": [0.1, 0.1]}}]:
        validate_metric(spec)
    validate_metric({"metric": "mine", "topics": ["/a"]}, custom={"mine": len})

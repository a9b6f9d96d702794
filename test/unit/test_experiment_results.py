"""What a run leaves: its messages as numeric columns (real ROS messages flattened, their time,
the recording file's round trip), and the experiment's results folder (the JSONL record that a
resumed experiment reads back, a line cut by a crash, the CSV and Parquet tables)."""
import csv
import json
import math
import os

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, Range
from std_msgs.msg import Float64

from epuck_vrep_compat.experiment import flatten, metrics
from epuck_vrep_compat.experiment.results import ResultStore

XYZ, XYZW = ("x", "y", "z"), ("x", "y", "z", "w")
HEADER = ["header.seq", "header.stamp"]


def names(prefix, axes):
    return [f"{prefix}.{a}" for a in axes]


@pytest.mark.parametrize("cls, expected", [
    (Odometry, HEADER + names("pose.pose.position", XYZ) + names("pose.pose.orientation", XYZW)
     + names("twist.twist.linear", XYZ) + names("twist.twist.angular", XYZ)),
    (Range, HEADER + ["radiation_type", "field_of_view", "min_range", "max_range", "range"]),
    (Imu, HEADER + names("orientation", XYZW) + names("angular_velocity", XYZ)
     + names("linear_acceleration", XYZ)),
    (Twist, names("linear", XYZ) + names("angular", XYZ)),
    (Float64, ["data"]),
])
def test_the_numeric_fields_are_the_columns_and_covariances_are_left_out(cls, expected):
    assert [name for name, _path, _is_time in flatten.Columns(cls._type, cls).fields] == expected


def odometry(x, secs=0, nsecs=0):
    msg = Odometry()
    msg.header.stamp = rospy.Time(secs, nsecs)
    msg.header.seq = 7
    msg.pose.pose.position.x = x
    msg.pose.pose.orientation.w = 1.0
    msg.pose.covariance = [0.5] * 36
    msg.twist.twist.angular.z = -0.25
    return msg


def test_the_stamp_is_the_time_unless_it_is_zero_and_the_series_is_sorted():
    columns = flatten.Columns("nav_msgs/Odometry", Odometry)
    columns.add(odometry(0.3, 2, 500000000), 9.0)
    columns.add(odometry(0.1), 1.25)
    columns.add(odometry(0.2, 2, 0), 9.5)
    series = columns.series()
    assert series.type == "nav_msgs/Odometry"
    assert series.t.tolist() == [1.25, 2.0, 2.5]
    assert series.fields["pose.pose.position.x"].tolist() == [0.1, 0.2, 0.3]
    assert series.fields["header.stamp"].tolist() == [0.0, 2.0, 2.5]
    assert series.fields["header.seq"].tolist() == [7.0] * 3
    assert series.fields["pose.pose.orientation.w"].tolist() == [1.0] * 3
    assert series.fields["twist.twist.angular.z"].tolist() == [-0.25] * 3
    assert not any("covariance" in name for name in series.fields)


def test_messages_without_a_header_take_the_given_time():
    twist, value = flatten.Columns("geometry_msgs/Twist", Twist), flatten.Columns(
        "std_msgs/Float64", Float64)
    for now, speed in ((3.0, 0.5), (1.0, -0.5)):
        msg = Twist()
        msg.linear.x = speed
        twist.add(msg, now)
        value.add(Float64(data=speed * 4), now)
    assert twist.series().t.tolist() == [1.0, 3.0]
    assert twist.series().fields["linear.x"].tolist() == [-0.5, 0.5]
    assert value.series().fields["data"].tolist() == [-2.0, 2.0]


def test_a_recording_of_flattened_messages_round_trips(tmp_path):
    columns = {"/ePuck0/ground_truth": flatten.Columns("nav_msgs/Odometry", Odometry),
               "/ePuck0/proximity0": flatten.Columns("sensor_msgs/Range", Range),
               "/ePuck0/imu": flatten.Columns("sensor_msgs/Imu", Imu)}
    columns["/ePuck0/ground_truth"].add(odometry(0.125, 1), 0.0)
    columns["/ePuck0/proximity0"].add(Range(radiation_type=1, range=0.0625, max_range=0.1), 0.5)
    imu = Imu()
    imu.linear_acceleration.z = 9.75
    columns["/ePuck0/imu"].add(imu, 0.75)
    recording = {topic: c.series() for topic, c in columns.items()}
    path = str(tmp_path / "recording.npz")
    metrics.save_recording(path, recording)
    loaded = metrics.load_recording(path)
    assert sorted(loaded) == sorted(recording)
    for topic, series in recording.items():
        assert loaded[topic].type == series.type
        assert loaded[topic].t.tolist() == series.t.tolist()
        assert {k: v.tolist() for k, v in loaded[topic].fields.items()} == \
            {k: v.tolist() for k, v in series.fields.items()}
    assert loaded["/ePuck0/proximity0"].fields["radiation_type"].tolist() == [1.0]
    assert loaded["/ePuck0/proximity0"].fields["range"].tolist() == [0.0625]
    assert loaded["/ePuck0/imu"].fields["linear_acceleration.z"].tolist() == [9.75]


# --- the results folder ----------------------------------------------------------------------
ROWS = [
    {"run_key": "k1", "status": "ok", "seed": 0, "attempts": 1, "wall_s": 1.5, "exit_code": 0,
     "late_steps": 0, "host": "h1", "error": "", "param.sim.noise_preset": "vrep",
     "param.wander.speed": np.float64(0.04), "metric.distance_driven_m": np.float32(0.5),
     "metric.min_separation_m": float("nan"), "note": "x", "log_tail": ""},
    {"run_key": "k2", "status": "failed", "seed": np.int64(1), "attempts": 2, "wall_s": 0.0,
     "exit_code": None, "host": "h1", "error": "timed out", "param.sim.noise_preset": "real",
     "param.wander.speed": 0.08, "metric.coverage": float("inf"),
     "metric.min_separation_m": np.float64("nan"), "log_tail": "the, \"end\"\n"},
]
COLUMNS = ["run_key", "status", "seed", "attempts", "wall_s", "exit_code", "late_steps", "host",
           "error", "param.sim.noise_preset", "param.wander.speed", "metric.coverage",
           "metric.distance_driven_m", "metric.min_separation_m", "note", "log_tail"]
PLAIN = [  # the rows as the record keeps them: plain JSON values, NaN as null
    {**ROWS[0], "param.wander.speed": 0.04, "metric.distance_driven_m": 0.5,
     "metric.min_separation_m": None},
    {**ROWS[1], "seed": 1, "metric.min_separation_m": None},
]


@pytest.fixture
def store(tmp_path):
    store = ResultStore(str(tmp_path / "results"))
    for row in ROWS:
        store.add(row)
    return store


def record_lines(store):
    with open(store.record_path) as f:
        return f.read().splitlines()


def test_the_record_has_a_line_per_run_and_a_new_store_reads_it_back(store):
    lines = record_lines(store)
    assert [json.loads(line) for line in lines] == PLAIN
    assert type(json.loads(lines[1])["seed"]) is int
    assert json.loads(lines[1])["metric.coverage"] == math.inf
    assert store.rows == PLAIN
    assert store.done == {"k1", "k2"}
    again = ResultStore(store.out_dir)
    assert again.rows == PLAIN and again.done == {"k1", "k2"}


def test_a_line_cut_by_a_crash_is_skipped_and_the_next_row_kept(store):
    lines = record_lines(store)
    with open(store.record_path, "w") as f:
        f.write(lines[0] + "\n" + lines[1][:25])            # the crash: no end of line
    resumed = ResultStore(store.out_dir)
    assert resumed.rows == PLAIN[:1] and resumed.done == {"k1"}
    resumed.add(ROWS[1])
    assert ResultStore(store.out_dir).rows == PLAIN
    assert len(ResultStore(store.out_dir).rows) == 2


def test_the_csv_has_the_documented_columns_and_values(store):
    with open(os.path.join(store.out_dir, "results.csv"), newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
    assert reader.fieldnames == COLUMNS
    assert store.columns() == COLUMNS
    assert rows[0] == {"run_key": "k1", "status": "ok", "seed": "0", "attempts": "1",
                       "wall_s": "1.5", "exit_code": "0", "late_steps": "0", "host": "h1",
                       "error": "", "param.sim.noise_preset": "vrep",
                       "param.wander.speed": "0.04", "metric.coverage": "",
                       "metric.distance_driven_m": "0.5", "metric.min_separation_m": "",
                       "note": "x", "log_tail": ""}
    assert (rows[1]["seed"], rows[1]["exit_code"], rows[1]["late_steps"],
            rows[1]["metric.coverage"], rows[1]["log_tail"]) == ("1", "", "", "inf",
                                                                 "the, \"end\"\n")


def test_the_parquet_table_has_the_rows_and_typed_columns(store):
    table = pq.read_table(os.path.join(store.out_dir, "results.parquet"))
    assert table.column_names == COLUMNS
    types = {name: table.schema.field(name).type for name in COLUMNS}
    assert types == {**{c: pa.string() for c in ("run_key", "status", "host", "error",
                                                  "param.sim.noise_preset", "note",
                                                  "log_tail")},
                     **{c: pa.int64() for c in ("seed", "attempts", "exit_code", "late_steps")},
                     **{c: pa.float64() for c in ("wall_s", "param.wander.speed",
                                                  "metric.coverage", "metric.distance_driven_m",
                                                  "metric.min_separation_m")}}
    assert table.to_pylist() == [{c: row.get(c) for c in COLUMNS} for row in PLAIN]


def test_the_spec_is_kept_beside_the_results(store):
    store.save_spec({"name": "x", "declared": {"b", "a"}, "duration_s": 3.0})
    assert store.load_spec() == {"name": "x", "declared": ["a", "b"], "duration_s": 3.0}

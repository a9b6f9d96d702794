"""The safety benchmark's arithmetic on synthetic walks with answers known by hand: S_p with
the monitor's parameters, time in violation only while the robot moves, contacts, the
reaction per approach, the scale in effect (the watchdog's stop included), productivity; the
report's cells, worst walk and replay command; the coverage grid; the fault names."""
import json
import math

import numpy as np
import pytest

from epuck_vrep_compat.experiment import coverage_maps, report_safety, safety_cli
from epuck_vrep_compat.experiment import metrics_safety as ms
from epuck_vrep_compat.experiment.metrics import RunContext, TopicSeries
from epuck_vrep_compat.nodes.ssm_model import SsmParameters
from fake_ros import bench_script

STEP = 0.05


def test_monitor_parameters_take_the_runs_values_and_default_the_rest():
    p = ms.monitor_parameters({"monitor.reaction_time_s": 0.1, "fault.fault": "none"})
    assert p.reaction_time_s == 0.1
    assert p.stopping_time_s == SsmParameters().stopping_time_s


def test_scale_in_effect_holds_the_last_command_and_the_watchdog_stops():
    t = np.arange(6) * STEP
    applied = ms.scale_in_effect(t, [0.05, 0.15], [0.5, 1.0], [0.2], [1.0])
    assert applied.tolist() == [1.0, 0.5, 0.5, 1.0, 0.0, 0.0]
    assert ms.scale_in_effect(t).tolist() == [1.0] * 6


def test_reaction_is_signed_steps_per_approach():
    inside = [0, 0, 1, 1, 1, 0, 0, 0, 1, 1, 0]
    scale = [1, 1, 1, 1, 0.5, 1, 1, 0.2, 0.0, 0.0, 1]
    # first approach: inside at 2, slowed at 4 -> 2; second: slowed at 7, inside at 8 -> -1
    assert ms.reactions(np.array(inside, bool), scale) == [2, -1]


def test_a_scale_below_1_since_the_start_is_no_reaction():
    # the handshake's latched 0 never released: no slow-down after a scale of 1, no reaction
    # (it would read as -3: slowed at 0, inside at 3)
    inside = [0, 0, 0, 1, 1, 0]
    assert ms.reactions(np.array(inside, bool), [0.0] * 6) == []
    # released, then slowed again for the breach: that slow-down counts
    assert ms.reactions(np.array(inside, bool), [0.0, 1, 1, 1, 0.5, 0.5]) == [1]
    # a pre-emptive slow-down after a 1 still counts, negative
    assert ms.reactions(np.array(inside, bool), [0.0, 1, 0.5, 0.5, 0.5, 1]) == [-1]


def walk(separation, speed, scale, error=None):
    n = len(separation)
    t = np.arange(n) * STEP
    return ms.walk_metrics(t, separation, speed, [0.1] * n if error is None else error,
                           np.asarray(scale, float), SsmParameters())


def test_no_violation_while_the_robot_stands_however_close():
    m = walk([2.0, 0.5, 0.0, -0.1, 0.5], [0.0] * 5, [0.0] * 5)
    assert m["violation_s"] == 0.0 and m["contacts"] == 0
    assert m["touches"] == 1 and m["min_separation_m"] == -0.1
    assert m["productivity"] == 0.0 and math.isinf(m["cycle_time_ratio"])


def test_violation_and_contact_while_the_robot_moves():
    p = SsmParameters()
    s_p = p.human_speed_m_s * (p.reaction_time_s + p.stopping_time_s) + p.intrusion_m \
        + p.robot_uncertainty_m + 0.5 * (p.reaction_time_s + 0.5 * p.stopping_time_s)
    sep = [3.0, s_p + 0.01, s_p - 0.01, 0.0, 1.0, 3.0]
    m = walk(sep, [0.5] * 6, [1.0] * 6)
    assert m["violation_steps"] == 3            # below S_p at steps 2, 3 and 4
    assert m["violation_s"] == pytest.approx(3 * STEP)
    assert m["contacts"] == 1
    assert math.isnan(m["reaction_steps"])       # never slowed: no reaction
    assert m["productivity"] == 1.0


def test_tracker_error_ignores_steps_without_an_estimate():
    m = walk([3.0] * 4, [0.0] * 4, [1.0] * 4, error=[math.nan, 0.1, 0.2, 0.3])
    assert m["tracker_error_mean_m"] == pytest.approx(0.2)


def test_ssm_metrics_reads_the_recorded_topics():
    t = np.arange(5) * STEP
    truth = TopicSeries("geometry_msgs/Vector3Stamped", t,
                        {"vector.x": [3.0] * 5, "vector.y": [0.2] * 5, "vector.z": [0.05] * 5})
    scale = TopicSeries("std_msgs/Float64", t, {"data": [1.0, 1.0, 0.5, 0.5, 0.5]})
    ctx = RunContext(recording={ms.TRUTH_TOPIC: truth, "/IRB140/speed_scale": scale})
    m = ms.ssm_metrics(ctx)
    assert set(m) == set(ms.COLUMNS)
    assert m["productivity"] == pytest.approx(0.7)


def row(seed, monitor="ssm", fault="none", sep=1.0, violation=0.0, **params):
    r = {"status": "ok", "seed": seed, "run_key": f"k{seed}", "param.monitor.monitor": monitor,
         "param.fault.fault": fault, "metric.min_separation_m": sep,
         "metric.violation_s": violation, "metric.contacts": 0.0,
         "metric.reaction_steps": -3.0, "metric.productivity": 0.8,
         "metric.tracker_error_mean_m": 0.1}
    r.update({f"param.monitor.{k}": v for k, v in params.items()})
    return r


def test_report_cells_worst_walk_and_replay():
    rows = [row(0, violation=0.1), row(1, sep=0.4, violation=0.2),
            row(2, monitor="none", sep=-0.2, violation=1.5),
            row(3, reaction_time_s=0.1), {"status": "failed", "seed": 9, "run_key": "k9"}]
    cells = report_safety.cells(rows)
    assert list(cells)[0] == ("ssm", "none")
    assert ("ssm reaction_time_s=0.1", "none") in cells
    assert report_safety.worst_walk(cells[("ssm", "none")])["seed"] == 1
    command = report_safety.replay_command(rows[3])
    assert "seed:=3" in command and "reaction_time_s:=0.1" in command \
        and "monitor:=ssm" in command and "fault:=none" in command
    text = report_safety.markdown(rows, "t")
    assert "| ssm | none | 2 | 2 (0.30 s) | 0 | 0.40/0.43/0.70 |" in text
    assert "## Failed runs" in text


def test_coverage_grid_means_per_cell():
    x, y = np.array([-0.9, -0.9, 0.9]), np.array([-0.9, -0.9, 0.9])
    error, cameras = coverage_maps.grid(x, y, [0.1, 0.3, 0.5], [2, 1, 0], (2.0, 2.0), 1.0)
    assert error[0, 0] == pytest.approx(0.2) and error[1, 1] == pytest.approx(0.5)
    assert math.isnan(error[0, 1]) and cameras[0, 0] == 1.5 and cameras[1, 1] == 0.0
    s = coverage_maps.summary(error, cameras)
    assert s["seen_fraction"] == 0.5 and s["error_max_m"] == pytest.approx(0.5)


def test_fault_names():
    fault = bench_script("bench_fault")
    assert fault.parse_fault("latency_0.3") == ("latency", 0.3)
    assert fault.parse_fault("hidden_latency_0.3") == ("hidden_latency", 0.3)
    assert fault.parse_fault("monitor_killed") == ("monitor_killed", 0.0)
    for bad in ("latency_9", "hidden_latency_-1", "hidden_latency", "camera_exploded"):
        with pytest.raises(ValueError):
            fault.parse_fault(bad)


def test_a_hidden_latency_restamps_what_it_relays_and_a_visible_one_does_not():
    fault = bench_script("bench_fault")
    from geometry_msgs.msg import PoseWithCovarianceStamped
    import rospy
    old = PoseWithCovarianceStamped()
    old.header.stamp, old.header.frame_id = rospy.Time(4.0), "world"
    old.pose.pose.position.x = 1.5
    relay = fault.Fault.__new__(fault.Fault)
    relay.kind, relay.latency_s = "hidden_latency", 0.3
    out = relay.relayed(old, rospy.Time(4.3))
    assert (out.header.stamp, out.header.frame_id, out.pose.pose.position.x) == (
        rospy.Time(4.3), "world", 1.5)
    assert old.header.stamp == rospy.Time(4.0)            # the held estimate is not changed
    relay.kind = "latency"
    assert relay.relayed(old, rospy.Time(4.3)) is old


def test_timing_sums_the_wall_time_of_every_invocation(tmp_path):
    safety_cli.add_timing(str(tmp_path), 60.0, 200, 5)
    safety_cli.add_timing(str(tmp_path), 30.0, 200, 5)         # resumed
    with open(tmp_path / "timing.json") as f:
        timing = json.load(f)
    assert (timing["wall_s"], timing["invocations"]) == (90.0, 2)

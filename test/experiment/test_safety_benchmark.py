"""The safety benchmark (experiments/safety_ssm.yaml through ``safety_bench``) at a small size:
every monitor x fault cell over one walk and our supervisor over two, all ok, with the
results the arithmetic predicts for that walk; the same walk twice gives the same row; and the
coverage maps of both layouts."""
import glob
import math
import os
import re

import yaml

import evc_harness as h
from epuck_vrep_compat.experiment import coverage_maps
from repo import REPO

EXPERIMENTS = os.path.join(REPO, "experiments")


def test_every_cell_one_walk_and_the_report(tmp_path):
    """13 runs (12 cells x seed 0, and seed 1 of ssm at its defaults without a fault). Without
    a monitor the arm stays in the operator's S_p for seconds; our supervisor cuts that time;
    killed or fed a frozen estimate it leaves the arm stopped (the watchdog, the fail-safe);
    report.md holds the table and each monitor's worst walk as a replay command."""
    out = tmp_path / "out"
    code, stdout, stderr = h.run(["rosrun", "epuck_vrep_compat", "safety_bench", "run", "--out",
                                  str(out), "--walks", "2", "--cell-walks", "1", "--workers",
                                  "2", "--no-coverage"], tmp_path)
    assert code == 0, h.explain(code, stdout, stderr)
    rows = h.record(out / "walks")
    h.by_key(rows)
    assert len(rows) == 13 and {r["status"] for r in rows} == {"ok"}, h.describe(rows)

    def cell(monitor, fault="none", seed=0):
        """The row of that monitor at its defaults (no monitor.* parameter varied)."""
        chosen = [r for r in rows if r["param.monitor.monitor"] == monitor and r["seed"] == seed
                  and r["param.fault.fault"] == fault
                  and not any(k.startswith("param.monitor.") and k != "param.monitor.monitor"
                              for k in r)]
        assert len(chosen) == 1, h.describe(rows)
        return chosen[0]
    none, ssm = cell("none"), cell("ssm")
    assert none["metric.violation_s"] > 0.5, h.describe([none])
    assert ssm["metric.violation_s"] < none["metric.violation_s"], h.describe([ssm, none])
    assert none["metric.productivity"] == 1.0 and ssm["metric.productivity"] < 1.0
    for fault in ("monitor_killed", "tracker_frozen"):
        row = cell("ssm", fault)
        assert row["metric.final_scale"] == 0.0, h.describe([row])
    report = (out / "report.md").read_text()
    assert "| ssm | none | 2 |" in report, report
    assert "roslaunch ssm_bench replay.launch seed:=" in report, report


def first_cell_spec(folder, seeds, name="first_cell", extra_code=(), extra_packages=(),
                    **changes):
    """The shipped spec cut to its first cell (our supervisor at its defaults, no fault) and
    ``seeds``, with ``changes`` of its top keys and ``extra_code`` entries found in
    ``extra_packages`` (absolute paths), written to ``folder`` (its paths made absolute);
    returns its path."""
    with open(os.path.join(EXPERIMENTS, "safety_ssm.yaml")) as f:
        spec = yaml.safe_load(f)
    spec["vary"] = {"list": spec["vary"]["list"][:1]}
    spec["seeds"] = seeds
    spec.update(changes)
    spec["code"] += list(extra_code)
    spec["package_path"] = [os.path.join(EXPERIMENTS, p) for p in spec["package_path"]]
    spec["package_path"] += list(extra_packages)
    spec["simulator"]["launch"] = os.path.join(EXPERIMENTS, spec["simulator"]["launch"])
    for entry in spec["code"]:
        if "launch" in entry:
            entry["launch"] = os.path.join(EXPERIMENTS, entry["launch"])
    path = os.path.join(folder, f"{name}.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(spec, f)
    return path


def test_the_same_walk_twice_gives_the_same_row(tmp_path):
    """Issue 26: seed 0 of the first cell, run twice at once (two experiments, each its own
    ROS world): in lock-step every metric is the same to the last digit, the productivity,
    reaction and tracker error as well as the true separation (the tracker, the Kinect node and
    the supervisor each answer every step once from that step's inputs; the probe records the
    supervisor's unstamped scale at the step it answered)."""
    spec = first_cell_spec(tmp_path, [0])
    procs = [h.start(h.command(spec, tmp_path / f"out{k}", "--workers", 1), tmp_path)
             for k in (0, 1)]
    results = [h.finish(proc) for proc in procs]
    rows = []
    for k, (code, stdout, stderr) in enumerate(results):
        assert code == 0, h.explain(code, stdout, stderr)
        rows += h.record(tmp_path / f"out{k}")
    assert len(rows) == 2 and {r["status"] for r in rows} == {"ok"}, h.describe(rows)
    assert same_metrics(*rows) == {}, same_metrics(*rows)
    a = h.metrics_of(rows[0])
    assert 0.0 < a["metric.productivity"] < 1.0 and a["metric.tracker_error_mean_m"] > 0.0, a


def same_metrics(a, b):
    """The metrics of rows ``a`` and ``b`` that differ (NaN equals NaN): {name: (a, b)}."""
    a, b = h.metrics_of(a), h.metrics_of(b)
    assert a.keys() == b.keys() and len(a) > 10, (a, b)
    return {k: (a[k], b[k]) for k in a if not (a[k] == b[k] or (
        isinstance(a[k], float) and isinstance(b[k], float) and math.isnan(a[k])
        and math.isnan(b[k])))}


def test_walks_in_one_launch_give_the_rows_of_walks_launched_alone(tmp_path):
    """Issue 26's runs_per_launch: seeds 0, 1, 2 of the first cell (6 s walks) launched alone,
    in one launch whose nodes are all reset in place between the walks (their ``~reset``,
    after the simulator's rewind), and in one launch with a node that offers no reset as well
    (the fixtures' ``misbehave``: the probe has roslaunch start it again, and resets the rest),
    the three experiments at once: every metric the same to the last digit, the walks after
    a rewind as well as the first; the probes' logs say which nodes were reset and which
    started again."""
    misbehave = {"name": "misbehave", "node": "evc_fixture_nodes/misbehave",
                 "params": {"mode": "ok"}}
    specs = [first_cell_spec(tmp_path, [0, 1, 2], "alone", duration_s=6, runs_per_launch=1),
             first_cell_spec(tmp_path, [0, 1, 2], "reset", duration_s=6, runs_per_launch=3),
             first_cell_spec(tmp_path, [0, 1, 2], "mixed", duration_s=6, runs_per_launch=3,
                             extra_code=[misbehave], extra_packages=[h.fixture("pkgs")])]
    procs = []
    for k, spec in enumerate(specs):      # the runs' folders kept, each experiment's apart
        os.makedirs(tmp_path / f"tmp{k}")
        env = h.environment(tmp_path, EVC_KEEP_RUNS=1, TMPDIR=tmp_path / f"tmp{k}")
        procs.append(h.start(h.command(spec, tmp_path / f"out{k}", "--workers", 1), tmp_path,
                             env))
    results = [h.finish(proc) for proc in procs]
    for code, stdout, stderr in results:
        assert code == 0, h.explain(code, stdout, stderr)
    alone, reset, mixed = ({r["seed"]: r for r in h.record(tmp_path / f"out{k}")}
                           for k in range(3))
    assert alone.keys() == reset.keys() == mixed.keys() == {0, 1, 2}, h.describe(
        [*alone.values(), *reset.values(), *mixed.values()])
    assert {r["run_key"] for r in alone.values()} == {r["run_key"] for r in reset.values()}
    for seed, row in alone.items():
        for chunked in (reset[seed], mixed[seed]):
            assert row["status"] == chunked["status"] == "ok", h.describe([row, chunked])
            assert same_metrics(chunked, row) == {}, (seed, same_metrics(chunked, row))
            assert 0.0 < chunked["cpu_s"] and 0.0 < chunked["wall_s"], chunked
    nodes = "/fault, /kinect, /operator_tracker, /ssm_supervisor, /truth"
    assert probe_log_lines(tmp_path / "tmp1") == [f"reset {nodes}; started again none"] * 2
    assert probe_log_lines(tmp_path / "tmp2") == [f"reset {nodes}; started again /misbehave"] * 2


def probe_log_lines(runs_folder):
    """What the probe of the one chunk whose run folder is in ``runs_folder`` said of each walk
    after the first: which nodes it reset and which it had started again (timing cut off)."""
    logs = {os.path.realpath(path) for path in glob.glob(str(
        runs_folder / "evc-*" / "ros_home" / "log" / "*" / "experiment_probe*.log"))
            if not path.endswith(("-stdout.log", "-stderr.log"))}    # rospy's own, once
    assert len(logs) == 1, logs
    logs = list(logs)
    with open(logs[0]) as f:
        found = re.findall(r"experiment_probe: (reset .*; started again [^(]*) \(", f.read())
    return [line.strip() for line in found]


def test_coverage_maps_of_both_layouts(tmp_path):
    """The lawnmower walk in the thesis's layout and the alternative: a PNG each; the thesis's
    ceiling cameras leave the floor's south strip unseen, where the tracker coasts off, and the
    alternative (camera 0 moved over it) tracks him there: a smaller mean error."""
    code, stdout, stderr = h.run(["rosrun", "epuck_vrep_compat", "safety_bench", "coverage",
                                  str(tmp_path / "out")], tmp_path)
    assert code == 0, h.explain(code, stdout, stderr)
    for layout in ("thesis", "alternative"):
        path = tmp_path / "out" / f"coverage_{layout}.png"
        assert path.is_file() and os.path.getsize(path) > 10000, stdout
    rows = h.record(tmp_path / "out" / "coverage")
    assert {r["status"] for r in rows} == {"ok"}, h.describe(rows)
    error = {os.path.basename(r["param.sim.world"]).split("_")[0]: r["metric.tracker_error_mean_m"]
             for r in rows}
    assert 0.0 < error["alternative"] < error["thesis"], error
    # each bag holds the walk from its first step to its last (the probe starts the run once
    # rosbag record has subscribed): what the maps are drawn from does not depend on timing
    for row in rows:
        x, _, _, _ = coverage_maps.read_bag(
            str(tmp_path / "out" / "coverage" / "bags" / f"{row['run_key']}.bag"))
        assert len(x) == 1400, len(x)          # coverage.yaml's 70 s, in steps of 50 ms

"""From a checked spec to its runs and each run's launch file: the parameter cells (grid, list,
seeded random samples), where each varied name goes, what the runner forces on the simulator,
the run keys; then the generated launch file parsed back, and how launch files and nodes are
found."""
import copy
import io
import os
import re
import shlex
import xml.etree.ElementTree as ET

import pytest
import yaml

from epuck_vrep_compat.experiment import launch_files, plan, spec
from epuck_vrep_compat.experiment.cli import seeds_note
from epuck_vrep_compat.experiment.engine import Progress
from epuck_vrep_compat.experiment.spec_checks import Lines
from repo import REPO, fixtures_of

FIXTURES = fixtures_of("unit")
EPUCKS = os.path.join(REPO, "launch", "epucks.launch")
with open(os.path.join(FIXTURES, "valid.yaml"), encoding="utf-8") as _f:
    VALID_RAW = yaml.safe_load(_f)
ROUTED = {"sim.noise_preset": "vrep", "mine.speed": 0.1, "wander.speed": 0.2, "/gain/k": 3}


def spec_with(**changes):
    """The fixtures' valid spec, checked, with top keys replaced (None: removed)."""
    raw = copy.deepcopy(VALID_RAW)
    raw.update(changes)
    return spec.check({k: v for k, v in raw.items() if v is not None}, Lines(""), FIXTURES)


# --- cells -----------------------------------------------------------------------------------
def test_a_grid_is_the_product_of_its_values_last_name_fastest():
    assert plan.cells({"grid": {"a.x": [1, 2], "b.y": ["p", "q", "r"]}}) == [
        {"a.x": 1, "b.y": "p"}, {"a.x": 1, "b.y": "q"}, {"a.x": 1, "b.y": "r"},
        {"a.x": 2, "b.y": "p"}, {"a.x": 2, "b.y": "q"}, {"a.x": 2, "b.y": "r"}]


def test_a_list_is_its_cells_and_a_grid_times_a_list_their_product():
    cells = [{"a.x": 1, "b.y": "p"}, {"a.x": 5, "b.y": "q"}]
    assert plan.cells({"list": cells}) == cells
    assert plan.cells({"grid": {"c.z": [True, False]}, "list": cells}) == [
        {"c.z": True, "a.x": 1, "b.y": "p"}, {"c.z": True, "a.x": 5, "b.y": "q"},
        {"c.z": False, "a.x": 1, "b.y": "p"}, {"c.z": False, "a.x": 5, "b.y": "q"}]
    assert plan.cells({}) == [{}]


def test_a_cell_given_twice_is_one_cell():
    assert plan.cells({"grid": {"a.x": [1, 2, 1]}}) == [{"a.x": 1}, {"a.x": 2}]
    drawn = plan.cells(random_vary(50, 3, {"a.k": {"choice": ["p", "q"]}}))
    assert drawn == [{"a.k": "p"}, {"a.k": "q"}] or drawn == [{"a.k": "q"}, {"a.k": "p"}]


def random_vary(samples, seed, params):
    return {"random": {"samples": samples, "seed": seed, "params": params}}


DISTRIBUTIONS = {"a.u": {"uniform": [-1.0, 2.0]}, "a.l": {"loguniform": [0.01, 10.0]},
                 "a.i": {"integers": [1, 3]}, "a.c": {"choice": ["p", "q", 7]}}


def test_random_samples_follow_their_seed():
    first = plan.cells(random_vary(20, 4, DISTRIBUTIONS))
    assert len(first) == 20
    assert plan.cells(random_vary(20, 4, DISTRIBUTIONS)) == first
    assert plan.cells(random_vary(20, 5, DISTRIBUTIONS)) != first
    assert plan.cells(random_vary(5, 4, DISTRIBUTIONS)) == first[:5]


def test_random_samples_keep_to_their_distributions():
    cells = plan.cells(random_vary(400, 1, DISTRIBUTIONS))
    uniform = [c["a.u"] for c in cells]
    loguniform = [c["a.l"] for c in cells]
    assert all(type(v) is float and -1.0 <= v < 2.0 for v in uniform)
    assert min(uniform) < -0.9 and max(uniform) > 1.9
    assert all(type(v) is float and 0.01 <= v <= 10.0 for v in loguniform)
    # log-uniform: as many samples in each decade
    assert 0.25 < sum(v < 0.1 for v in loguniform) / 400 < 0.42
    assert {c["a.i"] for c in cells} == {1, 2, 3}
    assert all(type(c["a.i"]) is int for c in cells)
    assert {c["a.c"] for c in cells} == {"p", "q", 7}


# --- tasks -----------------------------------------------------------------------------------
def test_each_varied_name_goes_to_its_place():
    s = spec_with(vary={"list": [ROUTED]}, seeds=[4])
    [task] = plan.tasks(s, marker="m1")
    assert task.params == ROUTED
    assert task.sim_args == {"n": 1, "profile": "vrep", "noise_preset": "vrep", "seed": 4,
                             "paused": True, "rtf": 0.0}
    wander, mine = task.code
    assert wander["params"] == {"robot": "ePuck0", "speed": 0.2}
    assert mine["args"] == {"robot": "ePuck0", "speed": 0.1}
    assert "declared" not in mine
    assert task.global_params == {"/gain/k": 3}
    assert (task.seed, task.marker, task.experiment, task.spec_hash) == (4, "m1", s["name"],
                                                                         s["hash"])
    assert (task.duration_s, task.timeout_s, task.network) == (30.0, 720.0, "loopback")
    # the spec itself is left as it was, for the next run
    assert s["code"][1]["args"] == {"robot": "ePuck0"} and "speed" not in s["code"][0]["params"]


def test_the_run_seed_wins_and_a_user_rtf_is_kept():
    s = spec_with(simulator={"args": {"seed": 99, "rtf": 2.0, "paused": False}}, seeds=[7])
    assert [(t.sim_args["seed"], t.sim_args["rtf"], t.sim_args["paused"])
            for t in plan.tasks(s)] == [(7, 2.0, True)] * 4
    varied = spec_with(vary={"grid": {"sim.rtf": [0.5]}}, seeds=[1])
    assert plan.tasks(varied)[0].sim_args["rtf"] == 0.5


def test_wait_for_and_record_hold_the_metrics_topics_and_the_users():
    s = spec_with(pace={"wait_for": ["/*/cmd_vel"]}, record=["/ePuck0/imu"],
                  metrics=["distance_driven", {"metric": "score", "topics": ["/ePuck0/prox"],
                                               "function": "user_metrics.py:score"}])
    task = plan.tasks(s)[0]
    # what the code publishes must appear; what the metrics read is waited for where it exists
    assert task.pace["wait_for"] == ["/*/cmd_vel"]
    assert task.pace["also_wait_for"] == ["/*/ground_truth", "/ePuck0/prox"]
    assert task.record == ["/*/cmd_vel", "/*/ground_truth", "/ePuck0/imu", "/ePuck0/prox"]
    assert s["pace"]["wait_for"] == ["/*/cmd_vel"]


def test_runs_are_cells_outer_seeds_inner_with_unique_keys():
    s = spec_with(seeds=[5, 6])
    tasks = plan.tasks(s)
    assert [(t.params["sim.noise_preset"], t.params["wander.speed"], t.seed) for t in tasks] == [
        (preset, speed, seed) for preset in ("real_robot", "vrep") for speed in (0.04, 0.08)
        for seed in (5, 6)]
    assert len({t.key for t in tasks}) == 8
    assert [t.key for t in plan.tasks(spec_with(seeds=[5, 6]))] == [t.key for t in tasks]
    assert tasks[0].key == plan.run_key(s["hash"], tasks[0].params, 5)


def test_a_run_key_changes_with_each_of_its_parts():
    params = {"a.x": 1, "b.y": "p"}
    key = plan.run_key("abc", params, 3)
    assert key == plan.run_key("abc", {"b.y": "p", "a.x": 1}, 3)
    assert re.fullmatch(r"[0-9a-f]{16}", key)
    assert len({key, plan.run_key("abd", params, 3), plan.run_key("abc", params, 4),
                plan.run_key("abc", {"a.x": 2, "b.y": "p"}, 3)}) == 4


# --- the run's launch file -------------------------------------------------------------------
@pytest.fixture
def task(tmp_path):
    """A run with every kind of varied name, a bag folder and a recording path."""
    s = spec_with(vary={"list": [ROUTED]}, seeds=[4], bag_dir=str(tmp_path / "bags"),
                  record=["/*/cmd_vel"])
    s["code"][0]["params"]["note"] = "a<b & 'c'"
    s["code"][0]["params"]["text"] = "1.0"
    [task] = plan.tasks(s)
    task.recording_path = str(tmp_path / "run" / "recording.npz")
    return task


def launch_xml(task):
    return ET.fromstring(launch_files.run_launch(task))


def test_a_lockstep_pace_on_cmd_vel_makes_the_simulator_wait_for_the_commands():
    s = spec_with(pace={"wait_for": ["/ePuck*/cmd_vel", "/ePuck0/speed"], "step_timeout_s": 3},
                  seeds=[1])
    args = plan.tasks(s)[0].sim_args
    assert (args["lockstep_cmd_vel"], args["lockstep_timeout"]) == ('["/ePuck*/cmd_vel"]', 1.5)
    assert yaml.safe_load(args["lockstep_cmd_vel"]) == ["/ePuck*/cmd_vel"]
    free = spec_with(pace={"mode": "free", "wait_for": ["/ePuck0/cmd_vel"]}, seeds=[1])
    other = spec_with(pace={"wait_for": ["/ePuck0/speed"]}, seeds=[1])
    for t in (plan.tasks(free)[0], plan.tasks(other)[0], plan.tasks(spec_with(seeds=[1]))[0]):
        assert "lockstep_cmd_vel" not in t.sim_args and "lockstep_timeout" not in t.sim_args
    own = spec_with(pace={"wait_for": ["/ePuck0/cmd_vel"]}, seeds=[1],
                    simulator=dict(VALID_RAW["simulator"], args={"lockstep_timeout": 4.0}))
    assert plan.tasks(own)[0].sim_args["lockstep_timeout"] == 4.0      # the spec's wins
    undeclared = {"wait_for": ["/ePuck0/cmd_vel"], "mode": "lockstep"}
    assert launch_files.cmd_vel_lockstep(undeclared, {"n", "paused"}) == {}


def args_of(include):
    return {a.get("name"): a.get("value") for a in include.findall("arg")}


def test_the_launch_file_sets_the_parameters_and_includes_the_simulator(task):
    root = launch_xml(task)
    params = {p.get("name"): p.get("value") for p in root.findall("param")}
    assert params == {"/use_sim_time": "true", "/experiment/seed": "4",
                      "/experiment/run_key": task.key}
    assert {r.get("param"): yaml.safe_load(r.text) for r in root.findall("rosparam")} == \
        {"/gain/k": 3}
    sim, mine = root.findall("include")
    assert sim.get("file") == task.sim_launch
    assert args_of(sim) == {"n": "1", "profile": "vrep", "noise_preset": "vrep", "seed": "4",
                            "paused": "true", "rtf": "0.0"}
    assert mine.get("file") == os.path.join(FIXTURES, "mine.launch")
    assert args_of(mine) == {"robot": "ePuck0", "speed": "0.1"}


def test_the_launch_file_starts_the_users_node_with_its_parameters(task):
    [node] = [n for n in launch_xml(task).findall("node") if n.get("name") == "wander"]
    assert {k: node.get(k) for k in ("pkg", "type", "ns", "args")} == {
        "pkg": "epuck_vrep_compat", "type": "wander", "ns": "/", "args": ""}
    assert {r.get("param"): yaml.safe_load(r.text) for r in node.findall("rosparam")} == {
        "robot": "ePuck0", "speed": 0.2, "note": "a<b & 'c'", "text": "1.0"}
    assert [(r.get("from"), r.get("to")) for r in node.findall("remap")] == [
        ("cmd_vel", "/ePuck0/cmd_vel")]


def test_the_launch_file_starts_the_probe_required_with_its_settings(task):
    [probe] = [n for n in launch_xml(task).findall("node") if n.get("name") == "experiment_probe"]
    assert (probe.get("pkg"), probe.get("type"), probe.get("required")) == \
        ("epuck_vrep_compat", "experiment_probe", "true")
    [settings] = probe.findall("rosparam")
    assert settings.get("param") is None
    assert yaml.safe_load(settings.text) == {"duration_s": 30.0, "out": task.recording_path,
                                             "topics": task.record, "pace": task.pace}
    assert task.record == ["/*/cmd_vel", "/*/ground_truth"]


def bag_nodes(task):
    return [n for n in launch_xml(task).findall("node") if n.get("pkg") == "rosbag"]


def test_a_bag_records_exactly_the_recorded_topics(task):
    [bag] = bag_nodes(task)
    assert bag.get("type") == "record"
    out, regex = shlex.split(bag.get("args"))[1::2]
    assert shlex.split(bag.get("args"))[::2] == ["-O", "-e"]
    assert out == os.path.join(os.path.dirname(task.recording_path), "run.bag")
    pattern = re.compile(regex)
    matched = [t for t in ("/ePuck0/ground_truth", "/ePuck12/cmd_vel", "/ePuck0/imu",
                           "/ePuck0/ground_truth_x", "/ground_truth", "/a/cmd_vel/b")
               if pattern.fullmatch(t)]
    assert matched == ["/ePuck0/ground_truth", "/ePuck12/cmd_vel"]
    # rosbag looks for the topics of a pattern on a timer of ROS time: the probe cannot wait
    assert "recorder" not in probe_settings(task)


def test_a_bag_of_named_topics_subscribes_at_once_and_the_probe_waits_for_it(task):
    task.record = ["/ePuck0/ground_truth", "/ePuck0/cmd_vel"]
    [bag] = bag_nodes(task)
    assert shlex.split(bag.get("args"))[2:] == task.record
    assert probe_settings(task)["recorder"] == "/" + bag.get("name")


def probe_settings(task):
    [probe] = [n for n in launch_xml(task).findall("node") if n.get("name") == "experiment_probe"]
    return yaml.safe_load(probe.find("rosparam").text)


def test_no_bag_without_a_bag_folder(task):
    task.bag_dir = None
    assert bag_nodes(task) == []
    assert "recorder" not in probe_settings(task)


# --- finding launch files and nodes ----------------------------------------------------------
def test_declared_args_are_the_settable_ones(tmp_path):
    assert launch_files.declared_args(os.path.join(FIXTURES, "mine.launch")) == {
        "robot", "speed", "gain"}
    assert launch_files.declared_args(os.path.join(FIXTURES, "plain.launch")) == set()
    assert "seed" in launch_files.declared_args(EPUCKS)
    assert launch_files.declared_args(str(tmp_path / "none.launch")) is None
    (tmp_path / "broken.launch").write_text("<launch><arg name='x'></launch>")
    assert launch_files.declared_args(str(tmp_path / "broken.launch")) is None


@pytest.mark.parametrize("value, base, expected", [
    (EPUCKS, "/", EPUCKS),
    ("mine.launch", FIXTURES, os.path.join(FIXTURES, "mine.launch")),
    ("fixtures/mine.launch", os.path.join(REPO, "test", "unit"),
     os.path.join(FIXTURES, "mine.launch")),
    ("epuck_vrep_compat/launch/epucks.launch", "/", EPUCKS),
    ("epuck_vrep_compat/epucks.launch", "/", EPUCKS),
    ("epuck_vrep_compat/nothing.launch", "/", None),
    ("no_such_package/epucks.launch", "/", None),
    ("nothing.launch", FIXTURES, None),
])
def test_resolve_finds_a_launch_file_by_path_or_package(value, base, expected):
    found = launch_files.resolve(value, base)
    assert (found if found is None else os.path.realpath(found)) == expected
    assert found is None or os.path.isabs(found)


def test_find_node_finds_an_executable_as_rosrun_does():
    assert os.path.realpath(launch_files.find_node("epuck_vrep_compat", "wander")) == \
        os.path.join(REPO, "scripts", "wander")
    assert launch_files.find_node("epuck_vrep_compat", "no_such_node") is None
    assert launch_files.find_node("no_such_package", "wander") is None


def test_more_seeds_asked_than_the_spec_has_says_so_and_how_to_add_them():
    """``--seeds N`` beyond the spec's seeds runs the spec's and says that no new one runs and
    which key adds them; within them it says nothing."""
    assert seeds_note(3, [0, 1, 2]) is None
    assert seeds_note(1, [0, 1, 2]) is None
    note = seeds_note(50, list(range(30)))
    assert "--seeds 50" in note and "(30)" in note and "no new ones" in note
    assert "'seeds: 50'" in note


def test_a_retried_run_says_why_its_first_attempt_failed():
    """The row keeps only the last attempt's error: the progress says the first one's."""
    stream = io.StringIO()
    Progress(3, 0, stream=stream).retry({"run_key": "abc", "attempts": 1, "status": "failed",
                                          "error": "timed out after 8 s of wall time"})
    assert stream.getvalue() == ("experiment: run abc attempt 1 failed: timed out after 8 s of "
                                 "wall time; running it again\n")

"""Several runs in one launch (the spec's ``runs_per_launch``): the setting's checks, the
grouping of a cell's runs into launches, the launch file of a chunk (the user's nodes respawn,
the probe gets every walk), and how a chunk's costs are split between its rows."""
import copy
import json
import os
import tempfile
import threading
import xml.etree.ElementTree as ET

import pytest
import yaml

from epuck_vrep_compat.experiment import (
    engine, flatten, launch_files, plan, probe, probe_walks, runner_chunk, spec)
from epuck_vrep_compat.experiment.spec_checks import Lines, SpecError
from repo import fixtures_of

FIXTURES = fixtures_of("unit")
with open(os.path.join(FIXTURES, "valid.yaml"), encoding="utf-8") as _f:
    VALID_RAW = yaml.safe_load(_f)
# the fixtures' spec without its launch-file code entry (mine.launch declares no respawn_nodes)
NODES_ONLY = [c for c in VALID_RAW["code"] if "node" in c]


def spec_with(**changes):
    raw = copy.deepcopy(VALID_RAW)
    raw.update(changes)
    return spec.check({k: v for k, v in raw.items() if v is not None}, Lines(""), FIXTURES)


def problems_of(**changes):
    with pytest.raises(SpecError) as error:
        spec_with(**changes)
    return str(error.value)


# --- the setting -------------------------------------------------------------------------------
def test_one_run_per_launch_by_default_and_a_number_or_a_mapping_sets_it():
    assert spec_with()["runs_per_launch"] == {"runs": 1, "alone": []}
    assert spec_with(code=NODES_ONLY, runs_per_launch=4)["runs_per_launch"] == \
        {"runs": 4, "alone": []}
    alone = [{"wander.speed": 0.08}]
    assert spec_with(code=NODES_ONLY, runs_per_launch={"runs": 3, "alone": alone})[
        "runs_per_launch"] == {"runs": 3, "alone": alone}


@pytest.mark.parametrize("value, needle", [
    (0, "runs_per_launch.runs"), (True, "a number of runs"), ("5", "a number of runs"),
    ({"runs": 2.5}, "whole number >= 1"), ({"runs": 2, "every": 1}, "unknown key"),
    ({"runs": 2, "alone": [{"wander.gain": 1}]}, "not a varied parameter"),
    ({"runs": 2, "alone": {"wander.speed": 1}}, "list of mappings")])
def test_a_bad_setting_is_refused_with_its_path(value, needle):
    assert needle in problems_of(code=NODES_ONLY, runs_per_launch=value)


def test_more_than_one_run_needs_respawning_launch_files_and_no_bags():
    assert "declares no 'respawn_nodes' argument" in problems_of(runs_per_launch=2)
    assert "no bags" in problems_of(code=NODES_ONLY, runs_per_launch=2, bag_dir="/tmp/bags")
    spec_with(runs_per_launch=1)        # one run per launch: mine.launch as it is


def test_how_many_share_a_launch_leaves_the_run_keys_as_they_are():
    one = plan.tasks(spec_with(code=NODES_ONLY))
    five = plan.tasks(spec_with(code=NODES_ONLY, runs_per_launch=5))
    assert [t.key for t in one] == [t.key for t in five]


# --- grouping ----------------------------------------------------------------------------------
def test_a_cells_seeds_go_in_order_in_chunks_and_alone_cells_one_to_a_launch():
    s = spec_with(code=NODES_ONLY, seeds=5, runs_per_launch={
        "runs": 2, "alone": [{"sim.noise_preset": "vrep", "wander.speed": 0.08}]})
    chunks = plan.chunks(s, plan.tasks(s))
    shape = [(c[0].params["sim.noise_preset"], c[0].params["wander.speed"],
              [t.seed for t in c]) for c in chunks]
    assert shape[:3] == [("real_robot", 0.04, [0, 1]), ("real_robot", 0.04, [2, 3]),
                         ("real_robot", 0.04, [4])]
    assert shape[-5:] == [("vrep", 0.08, [s]) for s in range(5)]
    assert sorted(t.key for c in chunks for t in c) == sorted(t.key for t in plan.tasks(s))


def test_runs_done_already_leave_the_rest_chunked_and_retries_stay_apart():
    s = spec_with(code=NODES_ONLY, seeds=4, runs_per_launch=3)
    tasks = [t for t in plan.tasks(s) if t.seed != 1][:3]      # resumed: seed 1 is done
    assert [[t.seed for t in c] for c in plan.chunks(s, tasks)] == [[0, 2, 3]]
    retried = [tasks[0], tasks[1].with_attempt(2), tasks[2]]
    assert [[t.seed for t in c] for c in plan.chunks(s, retried)] == [[0], [2], [3]]


class _Store:
    """What ``engine.launches`` reads of a result store: its folder and the keys done."""

    def __init__(self, out_dir, done=()):
        self.out_dir, self.done = out_dir, set(done)


def test_jobs_on_one_cluster_run_a_shared_run_once_and_the_longest_launches_first():
    every = spec_with(code=NODES_ONLY, seeds=3, runs_per_launch={
        "runs": 3, "alone": [{"sim.noise_preset": "vrep", "wander.speed": 0.08}]})
    first_cell = {"list": [{"sim.noise_preset": "real_robot", "wander.speed": 0.04}]}
    headline = dict(every, seeds=list(range(6)), vary=first_cell)
    other = dict(every, duration_s=50)                 # another experiment, its own folder
    done = plan.tasks(headline)[5].key                 # resumed: the headline's seed 5 is done
    todo, total, already = engine.launches(
        [(headline, _Store("walks", [done])), (every, _Store("walks", [done])),
         (dict(other, vary=first_cell, seeds=[0]), _Store("other"))], "marker")
    shape = [(store.out_dir, len(chunk) * (50 if store.out_dir == "other" else 30),
              [t.seed for t in chunk]) for chunk, store in todo]
    # headline 6 + every 12, less the 3 seeds they share, + 1 other; seed 5 done
    assert (total, already) == (16, 1)
    # the headline's first launch, every's two other cells of three, the headline's rest, the
    # other experiment's run, every's alone cell, one to a launch
    assert [cost for _, cost, _ in shape] == [90, 90, 90, 60, 50, 30, 30, 30]
    assert shape[0] == ("walks", 90, [0, 1, 2]) and shape[3:5] == [
        ("walks", 60, [3, 4]), ("other", 50, [0])]
    assert shape[-3:] == [("walks", 30, [s]) for s in range(3)]
    keys = [(store.out_dir, t.key) for chunk, store in todo for t in chunk]
    assert len(keys) == len(set(keys)) == 15 and ("walks", done) not in keys


def test_runs_with_a_bag_are_one_to_a_launch():
    s = spec_with(code=NODES_ONLY, seeds=2, runs_per_launch=2)
    tasks = plan.tasks(s)
    for t in tasks:
        t.bag_dir = "/tmp/bags"
    assert [len(c) for c in plan.chunks(s, tasks)] == [1, 1, 1, 1, 1, 1, 1, 1]


# --- the chunk's launch file -------------------------------------------------------------------
def test_a_chunks_launch_respawns_the_users_nodes_and_gives_the_probe_every_walk(tmp_path):
    s = spec_with(code=NODES_ONLY, seeds=2, runs_per_launch=2)
    lead = copy.copy(plan.tasks(s)[0])
    lead.walks = [{"seed": 0, "key": "a", "out": str(tmp_path / "walk0.npz")},
                  {"seed": 1, "key": "b", "out": str(tmp_path / "walk1.npz")}]
    lead.recording_path = lead.walks[0]["out"]
    root = ET.fromstring(launch_files.run_launch(lead))
    nodes = {n.get("name"): n for n in root.findall("node")}
    assert (nodes["wander"].get("respawn"), nodes["wander"].get("respawn_delay")) == \
        ("true", f"{launch_files.RESPAWN_DELAY_S:g}")
    assert nodes["experiment_probe"].get("respawn") is None
    settings = yaml.safe_load(nodes["experiment_probe"].find("rosparam").text)
    assert settings["walks"] == lead.walks
    assert probe_walks.walks_of(settings) == lead.walks
    alone = copy.copy(lead)
    alone.walks = []
    assert ET.fromstring(launch_files.run_launch(alone)).find("node").get("respawn") is None


def test_a_walk_after_the_first_waits_for_the_ready_messages_the_first_had():
    """The probe starts a walk after a reset only once each wait_for topic has had as many
    messages as when the launch's first walk started (a monitor's ready scale)."""
    from std_msgs.msg import Float64
    p = probe.Probe({"duration_s": 1.0, "out": "/x/walk0.npz",
                     "pace": {"mode": "lockstep", "wait_for": ["/s"]}})
    p.columns["/s"] = flatten.Columns("std_msgs/Float64", Float64)
    p.counts["/s"] = 0
    p.on_message(Float64(0.0), "/s")
    with p.lock:
        p.ready_counts = dict(p.counts)                  # as probe.start() notes it
    p.restart("/x/walk1.npz")
    with pytest.raises(RuntimeError, match="/s 0 of 1"):
        p.await_ready(0.0)                               # the deadline passed: no ready
    threading.Timer(0.01, p.on_message, (Float64(0.0), "/s")).start()
    p.await_ready(float("inf"))
    assert p.counts == {"/s": 1}


def test_one_run_is_a_walk_of_its_own_recording():
    assert probe_walks.walks_of({"out": "/x/recording.npz"}) == \
        [{"seed": None, "key": None, "out": "/x/recording.npz"}]


# --- costs ------------------------------------------------------------------------------------
def test_a_chunks_wall_and_cpu_time_are_split_between_its_rows():
    rows = [({"run_key": "a"}, {"probe": 1.0, "started": 4.0, "done": 10.0}),
            ({"run_key": "b"}, {"probe": 10.0, "started": 12.0, "done": 18.0})]
    outcome = {"cpu_s": 24.0, "times": {"launch": 0.0, "clean": 20.0}}
    a, b = runner_chunk._split_costs(rows, outcome)
    assert (a["wall_s"], b["wall_s"]) == (11.0, 9.0)            # own part + half the end
    assert (a["cpu_s"], b["cpu_s"]) == (13.2, 10.8)             # in proportion
    assert (a["startup_s"], a["stepping_s"], b["startup_s"], b["stepping_s"]) == (4, 6, 2, 6)
    assert a["teardown_s"] == b["teardown_s"] == 1.0


# --- a launch that ends mid-chunk ---------------------------------------------------------------
def fake_launch(done, monkeypatch, tmp_path):
    """runner's launch and run faked: the launch writes the status of the walks ``done`` (by
    index; "no_start" for the next one); a run alone gives an "alone" row."""
    alone = []

    def launch(lead, run_dir):
        for i, walk in enumerate(lead.walks):
            status = "done" if i in done else ("no_start" if i == len(done) else None)
            if status:
                with open(walk["out"][:-4] + ".status.json", "w") as f:
                    json.dump({"status": status, "times": {"done": float(i)}}, f)
        return {"cpu_s": 3.0, "times": {"launch": 0.0, "clean": 5.0}}

    def execute_run(task):
        alone.append(task.seed)
        return {"run_key": task.key, "seed": task.seed, "status": "alone"}
    monkeypatch.setattr(runner_chunk.runner, "launch", launch)
    monkeypatch.setattr(runner_chunk.runner, "judge",
                        lambda task, run_dir, outcome: {"status": "ok"})
    monkeypatch.setattr(runner_chunk.runner, "execute_run", execute_run)
    monkeypatch.setattr(runner_chunk.run_folders, "sweep_stale", lambda: None)
    monkeypatch.setattr(runner_chunk.run_folders, "make",
                        lambda experiment, key: tempfile.mkdtemp(dir=tmp_path))
    return alone


@pytest.mark.parametrize("done", [(0, 1, 2, 3), (0, 1), ()])
def test_the_runs_a_launch_did_not_finish_are_run_alone_none_lost_none_twice(
        done, monkeypatch, tmp_path):
    s = spec_with(code=NODES_ONLY, seeds=4, runs_per_launch=4)
    [chunk] = plan.chunks(s, plan.tasks(s)[:4])
    alone = fake_launch(done, monkeypatch, tmp_path)
    rows = runner_chunk.execute_chunk(chunk)
    assert [r["run_key"] for r in rows] == [t.key for t in chunk]
    assert [r["status"] for r in rows] == ["ok" if i in done else "alone" for i in range(4)]
    assert alone == [t.seed for i, t in enumerate(chunk) if i not in done]
    assert all(r["cpu_s"] > 0 for r in rows if r["status"] == "ok")

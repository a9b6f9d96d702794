"""The experiment spec's checks: a valid spec comes back with its defaults filled in; every bad
key is refused by its key path and the line of that key in the YAML text, all problems of a
spec together; and the spec hash, which keys the runs already done, is the same in every
process and moves only with what changes a run's result."""
import os
import re
import subprocess
import sys

import pytest
import yaml

from epuck_vrep_compat.experiment import spec
from epuck_vrep_compat.experiment.spec_checks import Lines, SpecError
from repo import REPO, fixtures_of

FIXTURES = fixtures_of("unit")
VALID = os.path.join(FIXTURES, "valid.yaml")
with open(VALID, encoding="utf-8") as _f:
    VALID_TEXT = _f.read()
with open(os.path.join(REPO, "launch", "epucks.launch"), encoding="utf-8") as _f:
    EPUCKS_ARGS = sorted(re.findall(r'<arg name="(\w+)"', _f.read()))


def edited(*replacements, text=VALID_TEXT):
    """The valid spec's text with each (old, new) replaced once; old must be there."""
    for old, new in replacements:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    return text


def checked(text):
    """``spec.check`` of a YAML text whose relative paths are the fixtures'."""
    return spec.check(yaml.safe_load(text), Lines(text), FIXTURES)


def problems_of(text):
    with pytest.raises(SpecError) as caught:
        checked(text)
    return caught.value.problems


def line_of(text, needle):
    """The 1-based line of the one line of ``text`` holding ``needle``."""
    found = [i + 1 for i, line in enumerate(text.splitlines()) if needle in line]
    assert len(found) == 1, (needle, found)
    return found[0]


def test_a_valid_spec_comes_back_with_its_defaults():
    s = spec.load(VALID)
    assert s["name"] == "obstacle_avoidance"
    assert s["base_dir"] == FIXTURES
    assert os.path.realpath(s["simulator"]["launch"]) == os.path.join(REPO, "launch",
                                                                      "epucks.launch")
    assert s["simulator"]["args"] == {"n": 1, "profile": "vrep"}
    assert sorted(s["simulator"]["declared"]) == EPUCKS_ARGS
    wander, mine = s["code"]
    assert wander == {"name": "wander", "kind": "node", "package": "epuck_vrep_compat",
                      "type": "wander", "params": {"robot": "ePuck0"}, "args": "",
                      "namespace": "/", "remap": {"cmd_vel": "/ePuck0/cmd_vel"}}
    assert mine == {"name": "mine", "kind": "launch",
                    "launch": os.path.join(FIXTURES, "mine.launch"),
                    "args": {"robot": "ePuck0"}, "declared": {"robot", "speed", "gain"}}
    assert s["vary"] == {"grid": {"sim.noise_preset": ["real_robot", "vrep"],
                                  "wander.speed": [0.04, 0.08]}}
    assert s["seeds"] == [0, 1, 2]
    assert s["duration_s"] == 30.0
    assert s["timeout_s"] == 120.0 + 20.0 * 30.0
    assert s["metrics"] == [{"metric": "distance_driven"}, {"metric": "score", "custom": True}]
    assert s["custom"]["score"]["function"] == "score"
    assert s["custom"]["score"]["file"] == os.path.join(FIXTURES, "user_metrics.py")
    assert (s["pace"]["mode"], s["pace"]["settle_s"], s["pace"]["wait_for"]) == \
        ("lockstep", 0.003, [])
    assert (s["pace"]["step_timeout_s"], s["pace"]["start_grace_s"]) == (1.0, 0.5)
    assert s["pace"]["skip_gone"] is False      # a crashed node's steps stay late
    assert (s["network"], s["record"], s["bag_dir"], s["reference"]) == \
        ("loopback", [], None, {})
    assert re.fullmatch(r"[0-9a-f]{12}", s["hash"])


@pytest.mark.parametrize("seeds_yaml, expected", [
    ("3", [0, 1, 2]), ("[7, 3]", [7, 3]), ("{first: 100, count: 2}", [100, 101])])
def test_seeds_as_a_count_a_list_or_a_range(seeds_yaml, expected):
    assert checked(edited(("seeds: 3", f"seeds: {seeds_yaml}")))["seeds"] == expected


def test_a_given_timeout_is_kept():
    assert checked(edited(("duration_s: 30", "duration_s: 30\ntimeout_s: 45")))[
        "timeout_s"] == 45.0


# (id, edits of the valid text, the key path named, a text on the key's line, the message's part)
GRID_SPEED = "    wander.speed: [0.04, 0.08]"


def random_gain(distribution):
    """The edit adding ``vary.random`` with one parameter, wander.gain, of ``distribution``."""
    return [("  grid:\n", "  random:\n    samples: 2\n    params:\n"
                          f"      wander.gain: {distribution}\n  grid:\n")]


BAD = [
    ("unknown top key", [("seeds: 3", "seeds: 3\ncolour: red")], "colour", "colour:",
     "unknown key; the keys are"),
    ("missing name", [("name: obstacle_avoidance\n", "")], "name", "description:",
     "required: letters, digits"),
    ("bad name", [("name: obstacle_avoidance", "name: obstacle avoidance!")], "name",
     "name: obstacle", "required: letters, digits"),
    ("missing duration", [("duration_s: 30\n", "")], "duration_s", "name: obstacle",
     "required: the simulated seconds"),
    ("negative duration", [("duration_s: 30", "duration_s: -5")], "duration_s",
     "duration_s", "must be a positive number of seconds, got -5"),
    ("simulator not a mapping", [("simulator:\n  launch: epuck_vrep_compat/launch/epucks.launch"
                                  "\n  args: {n: 1, profile: vrep}", "simulator: fast")],
     "simulator", "simulator: fast", "must be a mapping with 'launch' and 'args'"),
    ("unknown simulator key", [("  args: {n: 1,", "  speed: 2\n  args: {n: 1,")],
     "simulator.speed", "speed: 2", "unknown key; the keys are args, launch"),
    ("simulator launch missing", [("launch: epuck_vrep_compat/launch/epucks.launch",
                                   "launch: nowhere/none.launch")],
     "simulator.launch", "none.launch", "launch file 'nowhere/none.launch' not found"),
    ("simulator arg undeclared", [("profile: vrep}", "profile: vrep,\n    colour: red}")],
     "simulator.args.colour", "colour: red",
     f"not an argument of epucks.launch; it has {', '.join(EPUCKS_ARGS)}"),
    ("code without name", [("  - name: mine\n    launch:", "  - launch:")], "code.1.name",
     "- launch: mine.launch", "required: an identifier other than 'sim'"),
    ("code name a list", [("  - name: mine", "  - name: [mine]")], "code.1.name",
     "name: [mine]", "required: an identifier other than 'sim'"),
    ("two code names alike", [("  - name: mine", "  - name:  wander")], "code.1.name",
     "name:  wander", "'wander' names two entries"),
    ("launch and node", [("    launch: mine.launch", "    launch: mine.launch\n    node: a/b")],
     "code.1", "- name: mine", "needs exactly one of 'launch'"),
    ("node not PACKAGE/TYPE", [("node: epuck_vrep_compat/wander", "node: wander")],
     "code.0.node", "node: wander", "must be PACKAGE/TYPE"),
    ("node not found", [("node: epuck_vrep_compat/wander", "node: epuck_vrep_compat/nothing")],
     "code.0.node", "node: epuck_vrep_compat", "no executable 'nothing' in package"),
    ("launch arg undeclared", [("      robot: ePuck0", "      robot: ePuck0\n      n: 2")],
     "code.1.args.n", "      n: 2", "not an argument of mine.launch"),
    ("launch arg constant", [("      robot: ePuck0", "      robot: ePuck0\n      constant: 2")],
     "code.1.args.constant", "constant: 2", "not an argument of mine.launch"),
    ("arg of a launch file without args", [("launch: mine.launch", "launch: plain.launch")],
     "code.1.args.robot", "      robot: ePuck0", "not an argument of plain.launch"),
    ("vary unknown key", [("  grid:\n", "  sweep: [1]\n  grid:\n")], "vary.sweep", "sweep:",
     "unknown key; the keys are grid, list, random"),
    ("grid value not a list", [(GRID_SPEED, "    wander.speed: 0.04")], "vary.grid.wander.speed",
     "wander.speed", "must be a non-empty list of values"),
    ("grid name without owner", [(GRID_SPEED, "    speed: [1]")], "vary.grid.speed",
     "speed: [1]", "must be sim.ARG"),
    ("grid name sim.X undeclared", [(GRID_SPEED, "    sim.colour: [1]")], "vary.grid.sim.colour",
     "sim.colour", "the simulator's launch file has no argument 'colour'"),
    ("grid name of no code", [(GRID_SPEED, "    other.x: [1]")], "vary.grid.other.x", "other.x",
     "'other' is not 'sim' nor a code entry's name (sim, wander, mine)"),
    ("grid name of an undeclared arg", [(GRID_SPEED, "    mine.colour: [1]")],
     "vary.grid.mine.colour", "mine.colour", "the launch file of 'mine' has no argument"),
    ("bad global name", [(GRID_SPEED, "    /9lives: [1]")], "vary.grid./9lives", "9lives",
     "a global ROS parameter name must look like /a/b_c"),
    ("random distribution", random_gain("{normal: [0, 1]}"), "vary.random.params.wander.gain",
     "normal", "must be one of {uniform, loguniform,"),
    ("loguniform from zero", random_gain("{loguniform: [0, 1]}"),
     "vary.random.params.wander.gain.loguniform", "loguniform",
     "must be [low, high] with low < high and low > 0"),
    ("integers of floats", random_gain("{integers: [0.5, 3]}"),
     "vary.random.params.wander.gain.integers", "integers",
     "must be [low, high] with low < high, both integers"),
    ("seeds zero", [("seeds: 3", "seeds: 0")], "seeds", "seeds:", "must be a count"),
    ("seeds negative", [("seeds: 3", "seeds: [-1]")], "seeds", "seeds:", "must be a count"),
    ("seeds twice", [("seeds: 3", "seeds: [1, 1]")], "seeds", "seeds:", "lists a seed twice"),
    ("seeds without count", [("seeds: 3", "seeds: {first: 0}")], "seeds", "seeds:",
     "must be a count"),
    ("metric unknown", [("  - distance_driven", "  - distance_drive")], "metrics.0",
     "distance_drive", "unknown metric 'distance_drive'; the built-in metrics are"),
    ("metric option unknown", [("  - distance_driven", "  - {metric: coverage, colour: red}")],
     "metrics.0", "coverage", "metric 'coverage': unknown option 'colour'"),
    ("metrics writing one column", [("  - distance_driven", "  - distance_driven\n"
                                                          "  - distance_driven")],
     "metrics", "metrics:", "metrics[1] (distance_driven) and metrics[0] both write column"),
    ("metric file missing", [("user_metrics.py:score", "missing.py:score")],
     "metrics.1.function", "missing.py",
     f"cannot read {os.path.join(FIXTURES, 'missing.py')}"),
    ("metric function missing", [("user_metrics.py:score", "user_metrics.py:nothing")],
     "metrics.1.function", "nothing",
     "user_metrics.py:nothing: AttributeError: no function 'nothing' there"),
    ("metric raising", [("user_metrics.py:score", "raising_metrics.py:score")],
     "metrics.1.function", "raising",
     "raising_metrics.py:score: RuntimeError: broken on import"),
    ("pace mode", [("seeds: 3", "seeds: 3\npace:\n  mode: fast")], "pace.mode", "mode: fast",
     "must be 'lockstep'"),
    ("pace wait_for relative", [("seeds: 3", "seeds: 3\npace:\n  wait_for: [cmd_vel]")],
     "pace.wait_for", "wait_for", "must be a list of absolute topic names"),
    ("pace skip_gone", [("seeds: 3", "seeds: 3\npace:\n  skip_gone: maybe")], "pace.skip_gone",
     "skip_gone", "must be true or false"),
    ("network", [("seeds: 3", "seeds: 3\nnetwork: wifi")], "network", "network",
     "must be 'loopback'"),
    ("reference", [("seeds: 3", "seeds: 3\nreference:\n  distance_driven_m: far")],
     "reference", "reference:", "must map metric names to numbers"),
    ("bag_dir", [("seeds: 3", "seeds: 3\nbag_dir: 7")], "bag_dir", "bag_dir",
     "must be a folder path"),
]


@pytest.mark.parametrize("edits, path, needle, message", [b[1:] for b in BAD],
                         ids=[b[0] for b in BAD])
def test_each_bad_key_is_refused_by_its_path_and_line(edits, path, needle, message):
    text = edited(*edits)
    problems = problems_of(text)
    assert len(problems) == 1, problems
    prefix = f"line {line_of(text, needle)}: '{path}': "
    assert problems[0].startswith(prefix), (prefix, problems[0])
    assert message in problems[0][len(prefix):], problems[0]


def test_every_problem_is_reported_together_with_its_line():
    text = edited(("name: obstacle_avoidance", "name: bad name"),
                  ("duration_s: 30", "duration_s: 0"), ("seeds: 3", "seeds: 3\nnetwork: wifi"),
                  ("node: epuck_vrep_compat/wander", "node: epuck_vrep_compat/nothing"))
    with pytest.raises(SpecError) as caught:
        checked(text)
    problems = caught.value.problems
    assert [p.split(": ", 2)[:2] for p in problems] == [
        [f"line {line_of(text, needle)}", f"'{path}'"] for path, needle in (
            ("name", "name: bad"), ("code.0.node", "nothing"), ("duration_s", "duration_s"),
            ("network", "network"))]
    assert str(caught.value).startswith("<spec>: 4 problem(s) in the experiment spec:\n")


@pytest.mark.parametrize("edits, messages", [
    ([("seeds: 3", "seeds: 3\n1: x\ncolour: red")],
     ["'1': unknown key", "'colour': unknown key"]),
    ([(GRID_SPEED, "    1: [2]")], ["'vary.grid.1': a parameter name must be a string"]),
    ([("  - name: mine", "  - name: 5"), (GRID_SPEED, "    other.x: [1]")],
     ["'code.1.name': required: an identifier", "'other' is not 'sim' nor a code entry's name "
                                                "(sim, wander)"]),
], ids=["top", "grid", "code name"])
def test_a_number_for_a_name_is_refused_not_a_crash(edits, messages):
    problems = problems_of(edited(*edits))
    assert len(problems) == len(messages), problems
    assert all(m in p for m, p in zip(messages, problems)), problems


def test_a_yaml_syntax_error_names_its_line(tmp_path):
    path = tmp_path / "broken.yaml"
    path.write_text("name: x\nseeds: 3\n  duration_s: 30\n")
    with pytest.raises(SpecError) as caught:
        spec.load(str(path))
    [problem] = caught.value.problems
    assert problem.startswith("not valid YAML: ") and "line 3" in problem, problem


def test_a_missing_file_and_a_non_mapping_are_refused(tmp_path):
    with pytest.raises(SpecError, match="cannot read the spec: No such file"):
        spec.load(str(tmp_path / "none.yaml"))
    (tmp_path / "list.yaml").write_text("- 1\n- 2\n")
    with pytest.raises(SpecError, match="the spec must be a mapping"):
        spec.load(str(tmp_path / "list.yaml"))


def hash_of(text):
    return checked(text)["hash"]


def test_the_hash_is_the_same_in_another_process_with_other_string_hashes():
    code = ("import sys; from epuck_vrep_compat.experiment import spec; "
            "print(spec.load(sys.argv[1])['hash'])")
    hashes = {spec.load(VALID)["hash"]}
    for seed in ("1", "2"):
        env = dict(os.environ, PYTHONHASHSEED=seed)
        hashes.add(subprocess.run([sys.executable, "-c", code, VALID], env=env, check=True,
                                  capture_output=True, text=True).stdout.strip())
    assert len(hashes) == 1, hashes


SAME_RESULTS = {
    "seeds": ("seeds: 3", "seeds: 30"),
    "vary": ("[0.04, 0.08]", "[0.04, 0.08, 0.12]"),
    "description": ("the experiment tests' valid spec", "another text"),
    "reference": ("seeds: 3", "seeds: 3\nreference: {distance_driven_m: 1.5}"),
    "timeout": ("duration_s: 30", "duration_s: 30\ntimeout_s: 99"),
}
OTHER_RESULTS = {
    "duration": ("duration_s: 30", "duration_s: 31"),
    "simulator arg": ("profile: vrep}", "profile: epuck_driver}"),
    "code param": ("params: {robot: ePuck0}", "params: {robot: ePuck1}"),
    "metric": ("  - distance_driven", "  - coverage"),
}


@pytest.mark.parametrize("edit", SAME_RESULTS.values(), ids=list(SAME_RESULTS))
def test_the_hash_ignores_what_does_not_change_a_run(edit):
    assert hash_of(edited(edit)) == hash_of(VALID_TEXT)


@pytest.mark.parametrize("edit", OTHER_RESULTS.values(), ids=list(OTHER_RESULTS))
def test_the_hash_follows_what_changes_a_run(edit):
    assert hash_of(edited(edit)) != hash_of(VALID_TEXT)


def package_hash(folder):
    """The valid spec's hash with ``folder`` as its one package_path folder."""
    checked_spec = dict(checked(VALID_TEXT), package_path=[str(folder)])
    return spec.spec_hash(checked_spec)


def write_package(folder, script_text):
    (folder / "bench" / "scripts").mkdir(parents=True)
    (folder / "bench" / "scripts" / "bench_truth").write_text(script_text)
    (folder / "bench" / "launch").mkdir()
    (folder / "bench" / "launch" / "run.launch").write_text("<launch/>\n")


def test_the_hash_follows_the_files_under_package_path(tmp_path):
    write_package(tmp_path / "a", "print('v1')\n")
    before = package_hash(tmp_path / "a")
    write_package(tmp_path / "b", "print('v1')\n")                # the same files elsewhere
    assert package_hash(tmp_path / "b") == before
    (tmp_path / "b" / "bench" / "__pycache__").mkdir()           # not part of a run
    (tmp_path / "b" / "bench" / "__pycache__" / "x.pyc").write_bytes(b"\0")
    assert package_hash(tmp_path / "b") == before
    (tmp_path / "b" / "bench" / "scripts" / "bench_truth").write_text("print('v2')\n")
    assert package_hash(tmp_path / "b") != before                 # a changed script
    (tmp_path / "b" / "bench" / "scripts" / "bench_truth").write_text("print('v1')\n")
    (tmp_path / "b" / "bench" / "launch" / "run.launch").rename(
        tmp_path / "b" / "bench" / "launch" / "other.launch")
    assert package_hash(tmp_path / "b") != before                 # a renamed launch file

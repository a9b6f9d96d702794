"""The experiment spec: a YAML file read and checked whole before any run starts.

Every problem is collected, each naming the key's path and its line in the file, and raised
together as one ``SpecError``; nothing runs until the spec is clean. The format (documented
in ``docs/experiments.md``)::

    name: obstacle_avoidance            # [A-Za-z0-9_-]+
    simulator: {launch: epucks.launch, args: {world: ..., n: 1, profile: vrep}}
    code:                               # the user's ROS code, unchanged: launch files, nodes
      - {name: wander, node: epuck_vrep_compat/wander, params: {robot: ePuck0}}
      - {name: mine, launch: my_pkg/launch/mine.launch, args: {robot: ePuck0}}
    vary:                               # grid (product), list (cells), random (samples)
      grid: {sim.noise_preset: [real_robot, vrep], wander.speed_m_s: [0.04, 0.08]}
    seeds: 20                           # or [1, 2, 3] or {first: 100, count: 20}
    duration_s: 30                      # simulated seconds of each run
    metrics: [distance_driven, collisions, {metric: mine, function: my_metrics.py:score}]

A varied name says where it goes: ``sim.ARG`` a launch argument of the simulator, ``CODE.X``
a launch argument of the code entry ``CODE`` (a launch file) or its private parameter ``~X``
(a node), ``/NAME`` a global ROS parameter.
"""
import hashlib
import json
import os
import re

import yaml

from epuck_vrep_compat.experiment import launch_files, spec_code, spec_launches, spec_vary
from epuck_vrep_compat.experiment import spec_checks as checks
from epuck_vrep_compat.experiment.spec_checks import SpecError
from epuck_vrep_compat.experiment.spec_code import metrics_function

__all__ = ["SpecError", "load", "check", "spec_hash", "metrics_function"]

NAME_RE = re.compile(r"^[A-Za-z0-9_-]+$")
CODE_NAME_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
TOP_KEYS = {"name", "description", "package_path", "simulator", "code", "vary", "seeds",
            "duration_s",
            "timeout_s", "metrics", "record", "bag_dir", "pace", "network", "reference",
            "runs_per_launch"}
DEFAULT_SIM_LAUNCH = "epuck_vrep_compat/launch/epucks.launch"


def load(path):
    """The checked spec of the YAML file ``path`` as a plain dict with every default filled in
    (see the module's docstring), or ``SpecError`` naming every problem."""
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise checks.SpecError(path, [f"cannot read the spec: {e.strerror}"]) from None
    try:
        raw = yaml.safe_load(text)
        lines = checks.Lines(text)
    except yaml.YAMLError as e:
        raise checks.SpecError(path, [f"not valid YAML: {e}"]) from None
    return check(raw, lines, os.path.dirname(os.path.abspath(path)), path)


def check(raw, lines, base_dir, path="<spec>"):
    """``load``'s checks on an already parsed document."""
    problems = checks.Problems(lines)
    if not isinstance(raw, dict):
        raise checks.SpecError(path, ["the spec must be a mapping of keys (name, simulator, code, ...)"])
    for key in sorted(set(raw) - TOP_KEYS, key=str):     # YAML keys may be numbers
        problems.add((key,), f"unknown key; the keys are {', '.join(sorted(TOP_KEYS))}")
    spec = {"name": _name(raw, problems), "description": str(raw.get("description", "")),
            "base_dir": base_dir}
    spec["package_path"] = _package_path(raw.get("package_path", []), problems, base_dir)
    spec["simulator"] = _simulator(raw.get("simulator", {}), problems, base_dir)
    spec["code"] = _code(raw.get("code", []), problems, base_dir)
    spec["vary"] = spec_vary.vary(raw.get("vary", {}), problems, spec)
    spec["seeds"] = spec_vary.seeds(raw.get("seeds", 1), problems)
    spec["duration_s"] = checks.positive(raw, "duration_s", None, problems)
    spec["timeout_s"] = checks.positive(raw, "timeout_s", None, problems)
    if spec["timeout_s"] is None and spec["duration_s"] is not None:
        spec["timeout_s"] = 120.0 + 20.0 * spec["duration_s"]
    spec["metrics"], spec["custom"] = spec_code.metric_list(raw.get("metrics", []), problems, base_dir)
    spec["record"] = checks.string_list(raw, "record", problems)
    spec["bag_dir"] = raw.get("bag_dir")
    if spec["bag_dir"] is not None and not isinstance(spec["bag_dir"], str):
        problems.add(("bag_dir",), "must be a folder path (bags are copied there, one per run)")
    spec["pace"] = spec_code.pace(raw.get("pace", {}), problems)
    spec["network"] = raw.get("network", "loopback")
    if spec["network"] not in ("loopback", "all"):
        problems.add(("network",), "must be 'loopback' (the default: masters and nodes listen "
                                   "on 127.0.0.1 only) or 'all'")
    spec["runs_per_launch"] = spec_launches.runs_per_launch(raw.get("runs_per_launch"),
                                                            problems, spec)
    spec["reference"] = raw.get("reference", {})
    if not isinstance(spec["reference"], dict) or not all(
            isinstance(v, (int, float)) for v in spec["reference"].values()):
        problems.add(("reference",), "must map metric names to numbers")
    if problems.items:
        raise checks.SpecError(path, problems.items)
    spec["hash"] = spec_hash(spec)
    return spec


def spec_hash(spec):
    """What makes a run's result: everything but the list of cells and seeds, the texts and
    the paths of the outputs (so adding seeds or cells keeps the runs already done), and how
    many runs share a launch (a run's row is the same however many do). Files
    count by their contents, not where they are: a spec moved, or resumed on another machine
    with the same files, keeps its runs; so does every file under each ``package_path``
    folder (its scripts, nodes and included launch files), by path within it and contents."""
    keep = {k: v for k, v in spec.items()
            if k not in ("vary", "seeds", "description", "reference", "bag_dir", "base_dir",
                         "hash", "timeout_s", "package_path", "custom", "runs_per_launch")}
    keep["package_path"] = [folder_digest(folder) for folder in spec["package_path"]]
    keep["simulator"] = _portable(spec["simulator"])
    keep["code"] = [_portable(c) for c in spec["code"]]
    keep["custom"] = {name: src.get("source", src.get("module")) + ":" + src["function"]
                      for name, src in spec["custom"].items()}
    return hashlib.sha1(json.dumps(keep, sort_keys=True, default=str).encode()).hexdigest()[:12]


def folder_digest(folder):
    """SHA-1 of the sorted relative paths and contents of every file under ``folder``
    (hidden folders, ``__pycache__`` and ``*.pyc``, which do not change a run, left out)."""
    digest = hashlib.sha1()
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d != "__pycache__")
        for name in sorted(f for f in files if not f.endswith(".pyc")):
            path = os.path.join(root, name)
            digest.update(os.path.relpath(path, folder).replace(os.sep, "/").encode() + b"\0")
            with open(path, "rb") as f:
                digest.update(hashlib.sha1(f.read()).digest())
    return digest.hexdigest()


def _portable(entry):
    out = {k: v for k, v in entry.items() if k != "declared"}
    if out.get("launch"):
        with open(out["launch"], "rb") as f:
            out["launch"] = hashlib.sha1(f.read()).hexdigest()
    return out


def _name(raw, problems):
    name = raw.get("name")
    if not isinstance(name, str) or not NAME_RE.match(name):
        problems.add(("name",), "required: letters, digits, '_' and '-' only")
        return "experiment"
    return name


def _package_path(raw, problems, base_dir):
    """Folders of the user's ROS packages (e.g. a class's controllers), searched before
    ROS_PACKAGE_PATH when the spec is checked and in every run."""
    if not isinstance(raw, list) or not all(isinstance(p, str) for p in raw):
        problems.add(("package_path",), "must be a list of folders")
        return []
    folders = [os.path.normpath(os.path.join(base_dir, p)) for p in raw]
    for i, folder in enumerate(folders):
        if not os.path.isdir(folder):
            problems.add(("package_path", i), f"no folder {folder}")
    if folders:
        os.environ["ROS_PACKAGE_PATH"] = launch_files.package_path(folders)
    return folders


def _simulator(raw, problems, base_dir):
    if not isinstance(raw, dict):
        problems.add(("simulator",), "must be a mapping with 'launch' and 'args'")
        return {"launch": None, "args": {}, "declared": None}    # unknown, not none
    for key in sorted(set(raw) - {"launch", "args"}, key=str):
        problems.add(("simulator", key), "unknown key; the keys are args, launch")
    launch = _resolve_launch(raw.get("launch", DEFAULT_SIM_LAUNCH), ("simulator", "launch"),
                             problems, base_dir)
    args = checks.scalar_map(raw.get("args", {}), ("simulator", "args"), problems)
    declared = launch_files.declared_args(launch) if launch else None
    if declared is not None:
        for name in sorted(set(args) - declared):
            problems.add(("simulator", "args", name),
                         f"not an argument of {os.path.basename(launch)}; it has "
                         f"{', '.join(sorted(declared))}")
    return {"launch": launch, "args": args, "declared": declared}


def _resolve_launch(value, path, problems, base_dir):
    if not isinstance(value, str) or not value:
        problems.add(path, "must name a launch file: a path, or PACKAGE/path/in/package")
        return None
    found = launch_files.resolve(value, base_dir)
    if found is None:
        problems.add(path, f"launch file {value!r} not found (as a path, relative to the "
                           "spec's folder, or as PACKAGE/path inside a ROS package)")
    return found


def _code(raw, problems, base_dir):
    if not isinstance(raw, list):
        problems.add(("code",), "must be a list of launch files and nodes")
        return []
    entries, seen = [], set()
    for i, item in enumerate(raw):
        path = ("code", i)
        if not isinstance(item, dict):
            problems.add(path, "must be a mapping with 'name' and 'launch' or 'node'")
            continue
        name = item.get("name")
        if not isinstance(name, str) or not CODE_NAME_RE.match(name) or name == "sim":
            problems.add(path + ("name",), "required: an identifier other than 'sim', used "
                                           "to vary its arguments (NAME.arg)")
        elif name in seen:
            problems.add(path + ("name",), f"{name!r} names two entries")
        else:
            seen.add(name)
        kind = [k for k in ("launch", "node") if k in item]
        allowed = {"name", "launch", "args"} if kind == ["launch"] else \
            {"name", "node", "params", "args", "namespace", "remap"}
        if len(kind) != 1:
            problems.add(path, "needs exactly one of 'launch' (a launch file) or 'node' "
                               "(PACKAGE/TYPE, as rosrun takes them)")
            continue
        for key in sorted(set(item) - allowed):
            problems.add(path + (key,), f"unknown key; the keys are {', '.join(sorted(allowed))}")
        entries.append(_code_entry(item, kind[0], path, problems, base_dir))
    return entries


def _code_entry(item, kind, path, problems, base_dir):
    entry = {"name": item.get("name"), "kind": kind}
    if kind == "launch":
        entry["launch"] = _resolve_launch(item["launch"], path + ("launch",), problems, base_dir)
        entry["args"] = checks.scalar_map(item.get("args", {}), path + ("args",), problems)
        declared = launch_files.declared_args(entry["launch"]) if entry["launch"] else None
        entry["declared"] = declared
        for name in sorted(set(entry["args"]) - (set(entry["args"]) if declared is None
                                                 else declared)):
            problems.add(path + ("args", name), f"not an argument of {item['launch']}")
        return entry
    node = item["node"]
    valid = isinstance(node, str) and node.count("/") == 1 and all(node.split("/"))
    entry["package"], entry["type"] = node.split("/") if valid else ("invalid", "invalid")
    if not valid:       # one problem: no search for an executable it cannot name
        problems.add(path + ("node",), "must be PACKAGE/TYPE, e.g. epuck_vrep_compat/wander")
    elif launch_files.find_node(entry["package"], entry["type"]) is None:
        problems.add(path + ("node",), f"no executable {entry['type']!r} in package "
                                       f"{entry['package']!r}")
    entry["params"] = checks.scalar_map(item.get("params", {}), path + ("params",), problems)
    entry["args"] = item.get("args", "")
    if not isinstance(entry["args"], str):
        problems.add(path + ("args",), "must be the node's command-line arguments as one string")
    entry["namespace"] = str(item.get("namespace", "/"))
    entry["remap"] = checks.scalar_map(item.get("remap", {}), path + ("remap",), problems)
    return entry



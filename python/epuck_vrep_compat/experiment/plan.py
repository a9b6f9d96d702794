"""From a checked spec to the list of runs: parameter cells (grid × list × random samples)
times seeds, each run keyed by the spec's hash, its parameters and its seed."""
import copy
import hashlib
import itertools
import json
import os
from dataclasses import dataclass, field

import numpy as np

from epuck_vrep_compat.experiment import launch_files, metrics, spec_launches


@dataclass
class RunTask:
    """Everything one run needs, picklable: it travels to a Dask worker, which may be another
    machine with no shared file system (user metrics travel as source)."""
    key: str
    experiment: str
    spec_hash: str
    seed: int
    params: dict                       # the varied values, by their spec names
    sim_launch: str
    sim_args: dict
    code: list
    global_params: dict
    duration_s: float
    timeout_s: float
    record: list
    metrics: list
    custom: dict
    pace: dict
    network: str
    bag_dir: str = None
    world_path: str = None
    attempt: int = 1
    marker: str = ""                   # the experiment's process marker (see runner)
    package_path: list = field(default_factory=list)   # folders of the user's ROS packages
    recording_path: str = field(default="", repr=False)   # set on the worker
    # several runs in one launch (runs_per_launch): [{seed, key, out}], this run's first
    walks: list = field(default_factory=list, repr=False)

    def with_attempt(self, attempt):
        task = copy.copy(self)
        task.attempt = attempt
        return task


def cells(vary):
    """The parameter cells of ``vary`` (each a dict name -> value), in a stable order, each
    once: a cell twice (a grid's value given twice, random samples alike) would be one run
    key twice, which the engine cannot tell apart."""
    parts = []
    if "grid" in vary:
        names = list(vary["grid"])
        parts.append([dict(zip(names, values))
                      for values in itertools.product(*(vary["grid"][n] for n in names))])
    if "list" in vary:
        parts.append([dict(c) for c in vary["list"]])
    if "random" in vary:
        parts.append(_samples(vary["random"]))
    out = [{}]
    for part in parts:
        out = [{**a, **b} for a in out for b in part]
    # in the order of first appearance (a dict keeps its keys' first insertion)
    return list({json.dumps(c, sort_keys=True, default=str): c for c in out}.values())


def _samples(random):
    rng = np.random.default_rng(random["seed"])
    out = []
    for _ in range(random["samples"]):
        cell = {}
        for name, dist in random["params"].items():
            kind, bounds = next(iter(dist.items()))
            if kind == "uniform":
                cell[name] = float(rng.uniform(*bounds))
            elif kind == "loguniform":
                cell[name] = float(np.exp(rng.uniform(np.log(bounds[0]), np.log(bounds[1]))))
            elif kind == "integers":
                cell[name] = int(rng.integers(int(bounds[0]), int(bounds[1]), endpoint=True))
            else:
                cell[name] = bounds[int(rng.integers(len(bounds)))]
        out.append(cell)
    return out


def run_key(spec_hash, params, seed):
    text = json.dumps({"spec": spec_hash, "params": params, "seed": seed}, sort_keys=True,
                      default=str)
    return hashlib.sha1(text.encode()).hexdigest()[:16]


def tasks(spec, marker=""):
    """Every run of the spec, cells outer and seeds inner."""
    out = []
    for cell in cells(spec["vary"]):
        for seed in spec["seeds"]:
            out.append(_task(spec, cell, seed, marker))
    return out


def chunks(spec, tasks):
    """``tasks`` (of :func:`tasks`, some perhaps done already) in launches: lists of runs of one
    cell, in order, at most the cell's ``runs_per_launch`` each (``spec_launches``)."""
    setting = spec.get("runs_per_launch") or {"runs": 1, "alone": []}
    out = []
    for task in tasks:
        size = 1 if task.bag_dir else spec_launches.chunk_size(setting, task.params)
        last = out[-1] if out else None
        if last and len(last) < size and last[0].params == task.params \
                and last[0].attempt == task.attempt:
            last.append(task)
        else:
            out.append([task])
    return out


def _absolute(value, base_dir):
    """``value`` as an absolute path when it is a relative path to something in ``base_dir``."""
    if isinstance(value, str) and value and not value.startswith(("/", "$", "~")) and \
            os.path.exists(os.path.join(base_dir, value)):
        return os.path.normpath(os.path.join(base_dir, value))
    return value


def _task(spec, cell, seed, marker):
    sim_args = dict(spec["simulator"]["args"])
    declared = spec["simulator"].get("declared") or set()
    code = [copy.deepcopy({k: v for k, v in c.items() if k != "declared"}) for c in spec["code"]]
    by_name = {c["name"]: c for c in code}
    global_params = {}
    for name, value in cell.items():
        if name.startswith("/"):
            global_params[name] = value
            continue
        owner, _, key = name.partition(".")
        if owner == "sim":
            sim_args[key] = value
        else:
            entry = by_name[owner]
            if entry["kind"] == "launch" and key == "launch":
                entry["launch"] = launch_files.resolve(value, spec["base_dir"])
            else:
                entry["args" if entry["kind"] == "launch" else "params"][key] = value
    # a relative path in an argument means the spec's folder (roslaunch runs in the run's)
    sim_args = {k: _absolute(v, spec["base_dir"]) for k, v in sim_args.items()}
    for entry in code:
        for table in ("args", "params"):
            if isinstance(entry.get(table), dict):
                entry[table] = {k: _absolute(v, spec["base_dir"]) for k, v in entry[table].items()}
    # the run's seed and pace go to the simulator; it runs as fast as it can and waits to
    # be started by the probe
    if "seed" in declared:
        sim_args["seed"] = seed
    if "rtf" in declared:
        sim_args.setdefault("rtf", 0.0)
    if "paused" in declared:
        sim_args["paused"] = True
    for key, value in launch_files.cmd_vel_lockstep(spec["pace"], declared).items():
        sim_args.setdefault(key, value)     # the spec's own sim args win
    needed = metrics.topics_needed(spec["metrics"])
    # lockstep waits, after each step, for what the code answers (it must exist) and for what
    # the metrics read (those of it that exist: a metric may name alternatives)
    pace = dict(spec["pace"], also_wait_for=needed)
    record = sorted(set(needed) | set(spec["record"]) | set(spec["pace"]["wait_for"]))
    return RunTask(key=run_key(spec["hash"], cell, seed), experiment=spec["name"],
                   spec_hash=spec["hash"], seed=seed, params=cell,
                   sim_launch=spec["simulator"]["launch"], sim_args=sim_args, code=code,
                   global_params=global_params, duration_s=spec["duration_s"],
                   timeout_s=spec["timeout_s"], record=record, metrics=spec["metrics"],
                   custom=spec["custom"], pace=pace, network=spec["network"],
                   bag_dir=spec["bag_dir"], world_path=sim_args.get("world"), marker=marker,
                   package_path=spec["package_path"])

"""What a spec varies: its parameter cells (grid, list, seeded random samples), the names they
set (``sim.ARG``, ``CODE.X``, ``/NAME``) and the seeds."""
import re

from epuck_vrep_compat.experiment import launch_files

DISTRIBUTIONS = {"uniform": 2, "loguniform": 2, "integers": 2, "choice": None}


def seeds(raw, problems):
    """The list of seeds: a count, a list, or {first, count}."""
    if isinstance(raw, bool):
        raw = None
    if isinstance(raw, int) and raw > 0:
        return list(range(raw))
    if isinstance(raw, list) and raw and all(isinstance(s, int) and not isinstance(s, bool)
                                             and s >= 0 for s in raw):
        if len(set(raw)) != len(raw):
            problems.add(("seeds",), "lists a seed twice")
        return list(raw)
    if isinstance(raw, dict) and set(raw) == {"first", "count"} and all(
            isinstance(raw[k], int) and raw[k] >= 0 for k in raw) and raw["count"] > 0:
        return list(range(raw["first"], raw["first"] + raw["count"]))
    problems.add(("seeds",), "must be a count (30), a list of non-negative integers, or "
                             "{first: F, count: C}")
    return [0]


def vary(raw, problems, spec):
    """The checked ``vary`` mapping (grid, list, random)."""
    if not isinstance(raw, dict):
        problems.add(("vary",), "must be a mapping with grid, list and/or random")
        return {}
    for key in sorted(set(raw) - {"grid", "list", "random"}, key=str):
        problems.add(("vary", key), "unknown key; the keys are grid, list, random")
    vary = {}
    if "grid" in raw:
        grid = raw["grid"]
        if not isinstance(grid, dict) or not grid:
            problems.add(("vary", "grid"), "must map parameter names to lists of values")
        else:
            vary["grid"] = {}
            for name, values in grid.items():
                target(name, ("vary", "grid", name), problems, spec)
                if not isinstance(values, list) or not values:
                    problems.add(("vary", "grid", name), "must be a non-empty list of values")
                else:
                    vary["grid"][name] = [launch_value(name, v, ("vary", "grid", name, i),
                                                       problems, spec)
                                          for i, v in enumerate(values)]
    if "list" in raw:
        cells = raw["list"]
        if not isinstance(cells, list) or not cells or not all(isinstance(c, dict) for c in cells):
            problems.add(("vary", "list"), "must be a non-empty list of mappings "
                                           "{parameter: value, ...}")
        else:
            for i, cell in enumerate(cells):
                for name in cell:
                    target(name, ("vary", "list", i, name), problems, spec)
                    cell[name] = launch_value(name, cell[name], ("vary", "list", i, name),
                                              problems, spec)
            vary["list"] = cells
    if "random" in raw:
        vary["random"] = random_samples(raw["random"], problems, spec)
    return vary


def random_samples(raw, problems, spec):
    """The checked ``vary.random``: samples, seed and one distribution per parameter."""
    path = ("vary", "random")
    if not isinstance(raw, dict) or set(raw) - {"samples", "seed", "params"} or \
            not isinstance(raw.get("params"), dict):
        problems.add(path, "must be {samples: N, seed: S, params: {NAME: {uniform: [lo, hi]}}}")
        return {}
    samples, seed = raw.get("samples"), raw.get("seed", 0)
    if isinstance(samples, bool) or not isinstance(samples, int) or samples <= 0:
        problems.add(path + ("samples",), "must be a positive number of samples")
    if not isinstance(seed, int) or seed < 0:
        problems.add(path + ("seed",), "must be a non-negative integer")
    for name, dist in raw["params"].items():
        sub = path + ("params", name)
        target(name, sub, problems, spec)
        if not isinstance(dist, dict) or len(dist) != 1 or next(iter(dist)) not in DISTRIBUTIONS:
            problems.add(sub, f"must be one of {{{', '.join(DISTRIBUTIONS)}: ...}}")
            continue
        kind, bounds = next(iter(dist.items()))
        if kind == "choice":
            if not isinstance(bounds, list) or not bounds:
                problems.add(sub + (kind,), "must be a non-empty list of values")
        elif not (isinstance(bounds, list) and len(bounds) == 2 and all(
                isinstance(b, int if kind == "integers" else (int, float))
                and not isinstance(b, bool) for b in bounds) and bounds[0] < bounds[1]) or (
                kind == "loguniform" and bounds[0] <= 0):
            problems.add(sub + (kind,), "must be [low, high] with low < high" + {
                "loguniform": " and low > 0", "integers": ", both integers"}.get(kind, ""))
    return {"samples": samples, "seed": seed, "params": raw["params"]}


def target(name, path, problems, spec):
    """Checks a varied name: ``sim.ARG``, ``CODE.X`` or ``/GLOBAL``."""
    if not isinstance(name, str):
        problems.add(path, "a parameter name must be a string")
        return
    if name.startswith("/"):
        if not re.match(r"^(/[A-Za-z][A-Za-z0-9_]*)+$", name):
            problems.add(path, "a global ROS parameter name must look like /a/b_c")
        return
    owner, _, key = name.partition(".")
    if not key:
        problems.add(path, "must be sim.ARG (a simulator launch argument), CODE.X (an argument "
                           "or private parameter of the code entry CODE) or /NAME (a ROS "
                           "parameter)")
        return
    if owner == "sim":
        declared = spec["simulator"].get("declared")
        if declared is not None and key not in declared:
            problems.add(path, f"the simulator's launch file has no argument {key!r}")
        return
    entry = next((c for c in spec["code"] if c.get("name") == owner), None)
    if entry is None:
        names = ", ".join(["sim"] + [c["name"] for c in spec["code"]
                                     if isinstance(c.get("name"), str)])
        problems.add(path, f"{owner!r} is not 'sim' nor a code entry's name ({names})")
    elif entry["kind"] == "launch" and key != "launch" and entry.get("declared") is not None \
            and key not in entry["declared"]:
        problems.add(path, f"the launch file of {owner!r} has no argument {key!r}")


def launch_value(name, value, path, problems, spec):
    """A varied ``CODE.launch`` (another launch file for a launch entry: a class of students'
    controllers) must name a launch file that exists; returns it resolved."""
    if not isinstance(name, str):        # refused by ``target``
        return value
    owner, _, key = name.partition(".")
    entry = next((c for c in spec["code"] if c.get("name") == owner), None)
    if key != "launch" or entry is None or entry["kind"] != "launch":
        return value
    found = launch_files.resolve(value, spec["base_dir"]) if isinstance(value, str) else None
    if found is None:
        problems.add(path, f"launch file {value!r} not found")
    return value                         # as written: a run's key must not hold a path

"""The spec's metrics (built-in, checked by ``metrics.validate_metric``, and the user's own,
whose source travels with each run so that workers need no shared file system) and its pace
(how the probe steps the simulation)."""
import os

from epuck_vrep_compat.experiment import metrics

PACE_MODES = ("free", "lockstep")


def metric_list(raw, problems, base_dir):
    """(metric specs, user metrics' sources by name) of the spec's ``metrics`` list."""
    if not isinstance(raw, list):
        problems.add(("metrics",), "must be a list of metric names or {metric: NAME, ...}")
        return [], {}
    specs, custom = [], {}
    for i, item in enumerate(raw):
        path = ("metrics", i)
        item = {"metric": item} if isinstance(item, str) else item
        if not isinstance(item, dict) or not isinstance(item.get("metric"), str):
            problems.add(path, "must be a metric name or {metric: NAME, options...}")
            continue
        if "function" in item:
            source = custom_source(item, path, problems, base_dir)
            if source is not None:
                custom[item["metric"]] = source
            item = {**{k: v for k, v in item.items() if k != "function"}, "custom": True}
        try:
            metrics.validate_metric(item)
        except ValueError as e:
            problems.add(path, str(e))
            continue
        specs.append(item)
    try:
        metrics.columns(specs)
    except ValueError as e:
        problems.add(("metrics",), str(e))
    return specs, custom


def custom_source(item, path, problems, base_dir):
    """A user's metric ``FILE.py:FUNCTION`` (relative to the spec) or ``MODULE:FUNCTION``:
    its source travels with each run, so workers need no shared file system."""
    ref = item["function"]
    if not isinstance(ref, str) or ref.count(":") != 1:
        problems.add(path + ("function",), "must be FILE.py:FUNCTION or MODULE:FUNCTION")
        return None
    where, function = ref.split(":")
    if where.endswith(".py"):
        file_path = where if os.path.isabs(where) else os.path.join(base_dir, where)
        try:
            with open(file_path, encoding="utf-8") as f:
                source = {"file": file_path, "source": f.read(), "function": function}
        except OSError:
            problems.add(path + ("function",), f"cannot read {file_path}")
            return None
    else:
        source = {"module": where, "function": function}
    try:
        metrics_function(source)
    except Exception as e:          # the user's code: any error is a problem of the spec
        problems.add(path + ("function",), f"{ref}: {type(e).__name__}: {e}")
        return None
    return source


def metrics_function(source):
    """The callable of a user's metric from ``_custom_source``'s description."""
    if "module" in source:
        import importlib
        namespace = vars(importlib.import_module(source["module"]))
    else:
        namespace = {"__name__": "experiment_user_metrics", "__file__": source["file"]}
        exec(compile(source["source"], source["file"], "exec"), namespace)
    function = namespace.get(source["function"])
    if not callable(function):
        raise AttributeError(f"no function {source['function']!r} there")
    return function


def pace(raw, problems):
    """How the probe steps the simulation: ``lockstep`` (default) or ``free``."""
    if not isinstance(raw, dict):
        problems.add(("pace",), "must be {mode: free|lockstep, wait_for: [topics], ...}")
        return {"mode": "lockstep", "wait_for": [], "step_timeout_s": 1.0,
                "start_grace_s": 0.5, "settle_s": 0.003, "start_timeout_s": 60.0,
                "skip_gone": False}
    allowed = {"mode", "wait_for", "step_timeout_s", "start_grace_s", "settle_s",
               "start_timeout_s", "skip_gone"}
    for key in sorted(set(raw) - allowed, key=str):
        problems.add(("pace", key), f"unknown key; the keys are {', '.join(sorted(allowed))}")
    wait_for = raw.get("wait_for", [])
    mode = raw.get("mode", "lockstep")
    if mode not in PACE_MODES:
        problems.add(("pace", "mode"), "must be 'lockstep' (one step, then wait for wait_for; "
                                       "the default) or 'free' (as fast as it goes)")
    if not isinstance(wait_for, list) or not all(isinstance(t, str) and t.startswith("/")
                                                 for t in wait_for):
        problems.add(("pace", "wait_for"), "must be a list of absolute topic names or "
                                           "patterns (/*/cmd_vel)")
        wait_for = []
    pace = {"mode": mode, "wait_for": wait_for}
    for key, default in (("step_timeout_s", 1.0), ("start_grace_s", 0.5), ("settle_s", 0.003),
                         ("start_timeout_s", 60.0)):
        value = raw.get(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0:
            problems.add(("pace", key), "must be a non-negative number of seconds")
            value = default
        pace[key] = float(value)
    pace["skip_gone"] = raw.get("skip_gone", False)
    if not isinstance(pace["skip_gone"], bool):
        problems.add(("pace", "skip_gone"), "must be true or false")
        pace["skip_gone"] = False
    return pace

"""One run, on whichever machine runs it: ``execute_run(task) -> row``, the Dask task.

The run lives in a temporary folder of its own (its launch file, ``ROS_HOME``, logs and
recording) under a shepherd process (``shepherd.py``) that starts roslaunch on a free port and
leaves nothing behind. The row carries the run's parameters, seed, metrics, wall time and
exit status; a failure (the code crashed, the run hung past its time-out, nothing was
published) is a row too, with the tail of its log. ``cpu_s`` is the CPU time of all the run's
processes (the shepherd's reaped children): unlike the wall time, it does not grow with the
machine's load. Only the row (and, when asked, a bag copied to ``bag_dir``) leaves the
worker: no shared file system is needed.
"""
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

import yaml

from epuck_vrep_compat.experiment import isolation, launch_files, metrics, run_folders
from epuck_vrep_compat.experiment import spec as spec_mod

LOG_TAIL_CHARS = 2000
# roslaunch colours the line: "\x1b[31m[NAME] process has died [pid P, exit code C, ...":
# the name holds no bracket (else it would start at the colour code's)
DIED = re.compile(r"\[([^\[\]]+)\] process has died \[pid \d+, exit code (-?\d+)")
REQUIRED_DIED = re.compile(r"REQUIRED process \[([^\[\]]+)\] has died")
PORT_ATTEMPTS = 3


def execute_run(task):
    """Runs ``task`` (a ``plan.RunTask``) to its end and returns its row (a flat dict)."""
    started = time.monotonic()
    run_folders.sweep_stale()               # what interrupted runs on this machine left
    run_dir = run_folders.make(task.experiment, task.key)
    row = {"run_key": task.key, "seed": task.seed, "attempts": task.attempt,
           **{f"param.{k}": v for k, v in task.params.items()}}
    try:
        outcome = launch(task, run_dir)
        row.update(judge(task, run_dir, outcome))
    except Exception as e:                  # a row, whatever happened: never a lost run
        row.update(status="failed", error=f"{type(e).__name__}: {e}", exit_code=None,
                   log_tail=_tail(run_dir))
    finally:
        row["wall_s"] = round(time.monotonic() - started, 3)
        row["host"] = os.uname().nodename
        if task.bag_dir and os.path.isfile(os.path.join(run_dir, "run.bag")):
            os.makedirs(task.bag_dir, exist_ok=True)
            shutil.copy(os.path.join(run_dir, "run.bag"),
                        os.path.join(task.bag_dir, f"{task.key}.bag"))
        if not os.environ.get(run_folders.KEEP_RUNS):
            shutil.rmtree(run_dir, ignore_errors=True)
    return row


def launch(task, run_dir):
    """Writes the run's launch file and runs it under a shepherd; retried on another port
    when the master could not bind its port (another run took it first). With ``task.walks``
    the launch serves each walk in turn and ends after the last one's status."""
    task.recording_path = (task.walks[0]["out"] if task.walks
                           else os.path.join(run_dir, "recording.npz"))
    last = task.walks[-1]["out"] if task.walks else task.recording_path
    with open(os.path.join(run_dir, "run.launch"), "w") as f:
        f.write(launch_files.run_launch(task))
    for _ in range(PORT_ATTEMPTS):
        port = isolation.free_port()
        ros_home = os.path.join(run_dir, "ros_home")
        os.makedirs(os.path.join(ros_home, "log"), exist_ok=True)
        # the run marker names this execution (its folder): Dask runs a task again, same key
        # and attempt, when its worker dies, and the two shepherds must not end each other's
        env = isolation.run_environment(
            os.environ, port, ros_home, task.network, task.marker,
            f"{task.marker}:{task.key}:{task.attempt}:{os.path.basename(run_dir)}")
        if task.package_path:
            env["ROS_PACKAGE_PATH"] = launch_files.package_path(task.package_path, env)
        job = {"command": ["roslaunch", "--disable-title",
                           "-p", str(port), os.path.join(run_dir, "run.launch")],
               "env": env, "timeout_s": task.timeout_s * max(1, len(task.walks)),
               "parent": os.getpid(),      # the worker: gone already -> orphaned
               "done_file": os.path.splitext(last)[0] + ".status.json"}
        with open(os.path.join(run_dir, "shepherd_in.json"), "w") as f:
            json.dump(job, f)
        shepherd = subprocess.Popen([sys.executable, "-m", "epuck_vrep_compat.experiment.shepherd",
                                     run_dir], start_new_session=True, env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            run_folders.add_owner(run_dir, shepherd.pid)
            shepherd.wait()
        except BaseException:             # the task is cancelled: the shepherd ends the run
            shepherd.terminate()
            shepherd.wait()
            raise
        with open(os.path.join(run_dir, "shepherd.json")) as f:
            outcome = json.load(f)
        if "Address already in use" not in _read(os.path.join(run_dir, "launch.log")):
            return outcome
    return outcome


def judge(task, run_dir, outcome):
    """The row's status, error, costs and metrics of a run launched (``outcome``: the
    shepherd's) whose recording is ``task.recording_path``."""
    status = read_json(os.path.splitext(task.recording_path)[0] + ".status.json")
    log = _read(os.path.join(run_dir, "launch.log"))
    died = [(name, int(code)) for name, code in DIED.findall(log)
            if not name.startswith("experiment_probe") and int(code) not in (0, -2, -15)]
    out = {"exit_code": outcome.get("exit_code"), "late_steps": status.get("late_steps"),
           "cpu_s": outcome.get("cpu_s"), **phases(outcome.get("times", {}), status.get("times", {}))}
    if outcome.get("timed_out"):
        return {**out, "status": "failed", "error": f"timed out after {task.timeout_s:g} s of "
                "wall time", "log_tail": _tail(run_dir)}
    if outcome.get("stopped") or outcome.get("orphaned"):
        return {**out, "status": "failed", "error": "stopped before its end",
                "log_tail": _tail(run_dir)}
    if status.get("status") != "done":
        required = [n for n in REQUIRED_DIED.findall(log) if not n.startswith("experiment_probe")]
        why = (f"{required[0]} (required) died, which ended the run" if required else
               status.get("message") or "the run never started (no status from the probe)")
        return {**out, "status": "failed", "error": why, "log_tail": _tail(run_dir)}
    if died:
        name, code = died[0]
        return {**out, "status": "failed", "error": f"{name} died with exit code {code}",
                "log_tail": _tail(run_dir)}
    recording = metrics.load_recording(task.recording_path)
    ctx = metrics.RunContext(recording=recording, robots=metrics.robots_in(recording),
                             world=_world(status.get("world")), duration_s=task.duration_s,
                             params=task.params, seed=task.seed,
                             bag_path=_bag(run_dir))
    custom = {name: spec_mod.metrics_function(src) for name, src in task.custom.items()}
    values = metrics.compute(task.metrics, ctx, custom=custom)
    row = {**out, "status": "ok", "error": "", "log_tail": ""}
    row.update({f"metric.{k}": (float(v) if v is not None else math.nan)
                for k, v in values.items()})
    return row


def phases(shepherd_times, probe_times):
    """Where a run's wall time went [s]: ``startup_s`` from roslaunch's start to the first step
    (master, simulator, the code, the probe's grace), ``stepping_s`` the simulated time's
    steps, ``teardown_s`` from the probe's end to the last process gone."""
    t = {**shepherd_times, **probe_times}
    out = {}
    for name, (a, b) in {"startup_s": ("launch", "started"), "stepping_s": ("started", "done"),
                         "teardown_s": ("done", "clean")}.items():
        if a in t and b in t:
            out[name] = round(t[b] - t[a], 3)
    return out


def _bag(run_dir):
    path = os.path.join(run_dir, "run.bag")
    return path if os.path.isfile(path) else None


def _world(path):
    if not path or not os.path.isfile(path):
        return {}
    with open(path) as f:
        return yaml.safe_load(f) or {}


def _read(path):
    try:
        with open(path, errors="replace") as f:
            return f.read()
    except OSError:
        return ""


def read_json(path):
    """A JSON file's content, {} when it cannot be read."""
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def _tail(run_dir):
    """The end of roslaunch's output and of every node's log of the run."""
    parts = [_read(os.path.join(run_dir, "launch.log"))[-LOG_TAIL_CHARS:]]
    log_dir = os.path.join(run_dir, "ros_home", "log")
    for folder, _dirs, files in os.walk(log_dir):
        for name in sorted(files):
            if name.endswith("-stdout.log") or name.endswith("-stderr.log"):
                text = _read(os.path.join(folder, name)).strip()
                if text:
                    parts.append(f"--- {name}\n{text[-LOG_TAIL_CHARS // 2:]}")
    return "\n".join(parts)[-2 * LOG_TAIL_CHARS:]

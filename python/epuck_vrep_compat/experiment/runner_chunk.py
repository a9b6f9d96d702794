"""Several runs of one parameter cell in one launch (the spec's ``runs_per_launch``):
``execute_chunk(tasks) -> rows``, the Dask task of a chunk.

The chunk's first run's launch serves every run in turn (the probe rewinds the simulator and
starts the user's nodes again between them: :mod:`probe_walks`); each run gets the row it
would get launched alone (the same metrics, to the last digit), keyed by its own run key. A
run the launch did not finish (the launch died, a node did not come back, the time-out) is
run again alone, in this task, so that no run is lost nor recorded twice.

A row's ``wall_s`` is its own part of the launch (from the end of the run before it, or the
launch's start, to its end) plus an equal share of the launch's end; its ``cpu_s`` the
launch's CPU time split in proportion to those wall times (the processes are shared); its
``startup_s`` the time from that start to its first step, ``teardown_s`` its share of the end.
"""
import copy
import os
import shutil
import time

from epuck_vrep_compat.experiment import run_folders, runner


def execute_chunk(tasks):
    """The rows of ``tasks`` (``plan.RunTask``s of one cell), in their order."""
    if len(tasks) == 1:
        return [runner.execute_run(tasks[0])]
    run_folders.sweep_stale()
    lead = copy.copy(tasks[0])
    run_dir = run_folders.make(lead.experiment, lead.key)
    lead.walks = [{"seed": t.seed, "key": t.key, "out": os.path.join(run_dir, f"walk{i}.npz")}
                  for i, t in enumerate(tasks)]
    rows, again = [], []
    try:
        try:
            outcome = runner.launch(lead, run_dir)
        except Exception as e:           # noqa: BLE001 - every run is then run alone
            outcome = {"error": f"{type(e).__name__}: {e}"}
        finished = []
        # a run done is judged on its own: the launch's end (timed out, stopped) came after it
        done_outcome = {k: v for k, v in outcome.items()
                        if k not in ("timed_out", "stopped", "orphaned")}
        for task, walk in zip(tasks, lead.walks):
            status = runner.read_json(os.path.splitext(walk["out"])[0] + ".status.json")
            if status.get("status") != "done" or "error" in outcome:
                again.append(task)
                continue
            walk_task = copy.copy(task)
            walk_task.recording_path = walk["out"]
            row = {"run_key": task.key, "seed": task.seed, "attempts": task.attempt,
                   **{f"param.{k}": v for k, v in task.params.items()},
                   **runner.judge(walk_task, run_dir, done_outcome)}
            finished.append((row, status.get("times", {})))
        rows = _split_costs(finished, outcome)
    finally:
        if not os.environ.get(run_folders.KEEP_RUNS):
            shutil.rmtree(run_dir, ignore_errors=True)
    by_key = {row["run_key"]: row for row in rows}
    by_key.update({t.key: runner.execute_run(t) for t in again})
    return [by_key[t.key] for t in tasks]


def _split_costs(finished, outcome):
    """Each row's wall and CPU time, and its phases (see the module)."""
    times = outcome.get("times", {})
    host = os.uname().nodename
    start = times.get("launch")
    own = []
    for row, walk in finished:
        begin = start if start is not None else walk.get("probe")
        own.append((begin, walk))
        start = walk.get("done", start)
    end = times.get("clean", start) - start if finished and start is not None else 0.0
    share = end / max(1, len(finished))
    walls = [max(0.0, w.get("done", b or 0.0) - (b or 0.0)) + share for b, w in own]
    total_cpu, total_wall = outcome.get("cpu_s"), sum(walls)
    for (row, walk), (begin, _), wall in zip(finished, own, walls):
        row.update(wall_s=round(wall, 3), host=host, teardown_s=round(share, 3),
                   cpu_s=(round(total_cpu * wall / total_wall, 3)
                          if total_cpu is not None and total_wall > 0 else None))
        for name, (a, b) in {"startup_s": (begin, walk.get("started")),
                             "stepping_s": (walk.get("started"), walk.get("done"))}.items():
            if a is not None and b is not None:
                row[name] = round(b - a, 3)
    return [row for row, _ in finished]

"""Runs an experiment's runs on Dask distributed and collects their rows as they finish.

By default a ``LocalCluster`` sized to the machine (one single-threaded worker process per
core); given a scheduler address, any Dask cluster (``dask scheduler`` + ``dask worker`` on
other machines, or dask-jobqueue's ``SLURMCluster``: see docs/experiments.md). With the spec's
``runs_per_launch``, one task runs several runs of a cell in one launch
(``runner_chunk.py``) and gives their rows together; a failed one is retried alone. A worker that
dies mid-run has its run rescheduled by Dask (its shepherd sees the worker gone and ends the
run's processes); a run that fails (crashed code, time-out, nothing published) is retried once
and then recorded as failed; neither stops the experiment. Ctrl-C ends the experiment: the
cluster is closed and every process marked with the experiment's marker is ended.
"""
import os
import sys
import time
import uuid

from dask.distributed import Client, LocalCluster, as_completed

from epuck_vrep_compat.experiment import isolation, plan
from epuck_vrep_compat.experiment.runner_chunk import execute_chunk

MAX_ATTEMPTS = 2


class Progress:
    """A tqdm bar on a terminal; otherwise one line per finished run (for logs and CI)."""

    def __init__(self, total, already, stream=sys.stderr):
        self.total, self.done, self.already, self.failed = total, already, already, 0
        self.started = time.monotonic()
        self.stream = stream
        self.bar = None
        if stream.isatty():
            from tqdm import tqdm
            self.bar = tqdm(total=total, initial=already, unit="run", file=stream,
                            dynamic_ncols=True)

    def update(self, row):
        self.done += 1
        self.failed += row["status"] != "ok"
        elapsed = time.monotonic() - self.started
        new = self.done - self.already
        rate = new / elapsed * 3600.0 if elapsed > 0 and new > 0 else 0.0
        eta = (self.total - self.done) / rate * 3600.0 if rate > 0 else float("nan")
        if self.bar is not None:
            self.bar.set_postfix(failed=self.failed, runs_per_hour=f"{rate:.0f}")
            self.bar.update(1)
        else:
            print(f"experiment: run {row['run_key']} {row['status']} in {row['wall_s']:.1f} s "
                  f"({self.done}/{self.total} done, {self.failed} failed, {rate:.0f} runs/h, "
                  f"ETA {eta:.0f} s){': ' + row['error'] if row.get('error') else ''}",
                  file=self.stream, flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def make_client(scheduler=None, workers=None):
    """(client, cluster or None): the given scheduler's, or a local cluster of ``workers``
    processes (default: one per core)."""
    if scheduler:
        return Client(scheduler), None
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                           processes=True, dashboard_address=None, host="127.0.0.1")
    return Client(cluster), cluster


def run(spec, store, scheduler=None, workers=None, stream=sys.stderr):
    """Runs every run of ``spec`` not yet in ``store``; returns (ok, failed) counts of this
    call. Rows reach ``store`` as they finish."""
    store.save_spec(spec)
    marker = uuid.uuid4().hex
    every = plan.tasks(spec, marker)
    tasks = [t for t in every if t.key not in store.done]
    total = len(every)
    progress = Progress(total, total - len(tasks), stream)
    if not tasks:
        progress.close()
        return 0, 0
    client, cluster = make_client(scheduler, workers)
    ok = failed = 0
    futures, pending = as_completed(), {}

    def submit(chunk):              # one launch: one run, or several of a cell (runs_per_launch)
        key = f"run-{chunk[0].key}-{chunk[0].attempt}" + (f"-{len(chunk)}" if chunk[1:] else "")
        pending[key] = chunk
        futures.add(client.submit(execute_chunk, chunk, pure=False, key=key))
    try:
        for chunk in plan.chunks(spec, tasks):
            submit(chunk)
        for future in futures:
            chunk = pending.pop(future.key)
            for task, row in zip(chunk, _rows_of(future, chunk)):
                if row["status"] != "ok" and task.attempt < MAX_ATTEMPTS:
                    submit([task.with_attempt(task.attempt + 1)])      # again, alone
                    continue
                store.add(row)
                progress.update(row)
                ok += row["status"] == "ok"
                failed += row["status"] != "ok"
    finally:
        progress.close()
        client.close()
        if cluster is not None:
            cluster.close()
        isolation.sweep(isolation.EXPERIMENT_MARKER, marker)
    return ok, failed


def _rows_of(future, chunk):
    """The chunk's rows, in its order; a task Dask gave up on (its workers kept dying) gives
    a failed row for each of its runs."""
    try:
        return future.result()
    except Exception as e:
        return [{"run_key": task.key, "seed": task.seed, "attempts": task.attempt,
                 "status": "failed", "error": f"{type(e).__name__}: {e}", "wall_s": 0.0,
                 "exit_code": None, "log_tail": "",
                 **{f"param.{k}": v for k, v in task.params.items()}} for task in chunk]

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

Several experiments can share one cluster (:func:`run_all`, the safety benchmark's walks and
coverage runs): their launches are submitted together, the longest first (simulated time to
run), so that no worker waits for the last long launch of one experiment before the next
begins, and the short ones fill the end. The local cluster's own housekeeping is slowed to what
runs of seconds need (:data:`LOCAL_CLUSTER_CONFIG`: about 7 % of a core less for four idle
workers, measured in docs/safety_benchmark.md).
"""
import os
import sys
import time
import uuid

import dask
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

    def retry(self, row):
        """A failed attempt that runs again: why, so that a row that needed two attempts is
        not a mystery (the row keeps only the last attempt's error)."""
        text = (f"experiment: run {row['run_key']} attempt {row.get('attempts', 1)} "
                f"{row['status']}: {row.get('error') or 'no error given'}; running it again")
        if self.bar is not None:
            self.bar.write(text, file=self.stream)
        else:
            print(text, file=self.stream, flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()


# Dask's defaults suit tasks of milliseconds; a task here is a launch of seconds to minutes:
# no statistical profiler sampling every worker every 10 ms (a dashboard's view, and there is
# no dashboard), the event loop's health checked each second rather than every 20 ms, the
# process's resources and a worker's memory each second or two rather than 10 times a second.
LOCAL_CLUSTER_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.admin.system-monitor.gil.enabled": False,
    "distributed.worker.memory.monitor-interval": "1s",
}


def make_client(scheduler=None, workers=None):
    """(client, cluster or None): the given scheduler's, or a local cluster of ``workers``
    processes (default: one per core), with :data:`LOCAL_CLUSTER_CONFIG`."""
    if scheduler:
        return Client(scheduler), None
    dask.config.set(LOCAL_CLUSTER_CONFIG)       # read by the scheduler here and each worker
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                           processes=True, dashboard_address=None, host="127.0.0.1")
    return Client(cluster), cluster


def run(spec, store, scheduler=None, workers=None, stream=sys.stderr):
    """Runs every run of ``spec`` not yet in ``store``; returns (ok, failed) counts of this
    call. Rows reach ``store`` as they finish."""
    return run_all([(spec, store)], scheduler, workers, stream)


def launches(jobs, marker):
    """The launches of ``jobs`` ((spec, store) pairs) still to run, as (chunk, store), longest
    first (a stable order: the specs' own among equals), and (total, already done) run counts.
    A run two jobs share (the same key into the same store) is run once."""
    out, seen, total = [], set(), 0
    for spec, store in jobs:
        done = store.done
        every = [t for t in plan.tasks(spec, marker) if (store.out_dir, t.key) not in seen]
        seen.update((store.out_dir, t.key) for t in every)
        total += len(every)
        tasks = [t for t in every if t.key not in done]
        out += [(chunk, store, len(chunk) * float(spec.get("duration_s") or 1.0))
                for chunk in plan.chunks(spec, tasks)]
    out.sort(key=lambda launch: -launch[2])
    todo = [(chunk, store) for chunk, store, _ in out]
    return todo, total, total - sum(len(chunk) for chunk, _ in todo)


def run_all(jobs, scheduler=None, workers=None, stream=sys.stderr):
    """:func:`run` for several (spec, store) jobs on one cluster (see the module); returns
    (ok, failed) counts of this call."""
    for spec, store in jobs:
        store.save_spec(spec)
    marker = uuid.uuid4().hex
    todo, total, already = launches(jobs, marker)
    progress = Progress(total, already, stream)
    if not todo:
        progress.close()
        return 0, 0
    client, cluster = make_client(scheduler, workers)
    ok = failed = 0
    futures, pending = as_completed(), {}

    def submit(chunk, store):       # one launch: one run, or several of a cell (runs_per_launch)
        key = f"run-{chunk[0].key}-{chunk[0].attempt}" + (f"-{len(chunk)}" if chunk[1:] else "")
        pending[key] = (chunk, store)
        futures.add(client.submit(execute_chunk, chunk, pure=False, key=key))
    try:
        for chunk, store in todo:
            submit(chunk, store)
        for future in futures:
            chunk, store = pending.pop(future.key)
            for task, row in zip(chunk, _rows_of(future, chunk)):
                if row["status"] != "ok" and task.attempt < MAX_ATTEMPTS:
                    progress.retry(row)
                    submit([task.with_attempt(task.attempt + 1)], store)      # again, alone
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

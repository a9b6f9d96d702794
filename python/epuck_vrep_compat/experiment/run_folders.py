"""Run folders (``<tmp>/evc-<experiment>-<key>-*``) and the sweep of those an interrupted
experiment left behind.

A run's folder is removed by its worker when the run ends; a worker killed meanwhile (Ctrl-C
on the experiment, a dead Dask worker) never gets there, and its shepherd, which then ends the
run, leaves the folder too. So each folder names its owners in ``owners.json``: the worker
that made it and the shepherd that runs it, each as (pid, start time), a pid alone being
reusable. Every run, before it starts, removes the ``evc-*`` folders of its machine's temporary
folder (its user's) none of whose owners is alive (:func:`sweep_stale`); with
``EVC_KEEP_RUNS`` set, nothing is removed. A folder whose owners are not written yet is left.
"""
import json
import os
import shutil
import tempfile

from epuck_vrep_compat.experiment.isolation import process_identity

PREFIX = "evc-"
OWNERS = "owners.json"
KEEP_RUNS = "EVC_KEEP_RUNS"       # set (to anything) on the workers: run folders are kept


def make(experiment, key):
    """A new run folder, owned by this process."""
    run_dir = tempfile.mkdtemp(prefix=f"{PREFIX}{experiment}-{key}-")
    add_owner(run_dir, os.getpid())
    return run_dir


def add_owner(run_dir, pid):
    """``pid`` (a live process) owns ``run_dir`` too."""
    path = os.path.join(run_dir, OWNERS)
    owners = _read_owners(path) or []
    owners.append(process_identity(pid))
    with open(path + ".new", "w") as f:
        json.dump(owners, f)
    os.replace(path + ".new", path)


def sweep_stale(parent=None):
    """Removes the run folders under ``parent`` (the temporary folder) none of whose owners
    is alive; returns their paths."""
    if os.environ.get(KEEP_RUNS):
        return []
    parent = parent or tempfile.gettempdir()
    removed = []
    try:
        names = os.listdir(parent)
    except OSError:
        return []
    for name in names:
        run_dir = os.path.join(parent, name)
        if not name.startswith(PREFIX) or not _mine(run_dir):
            continue
        owners = _read_owners(os.path.join(run_dir, OWNERS))
        if owners and not any(o and process_identity(o[0]) == o for o in owners):
            shutil.rmtree(run_dir, ignore_errors=True)
            removed.append(run_dir)
    return removed


def _mine(path):
    try:
        return os.path.isdir(path) and os.stat(path).st_uid == os.getuid()
    except OSError:
        return False


def _read_owners(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None

"""Run folders left by interrupted runs are swept at the next run: those none of whose owners
(pid and start time) is alive; a live owner's, an unowned one's and, with EVC_KEEP_RUNS, every
folder stay."""
import json
import os
import subprocess
import sys

from epuck_vrep_compat.experiment import isolation, run_folders


def folder(parent, name, owners):
    path = parent / name
    path.mkdir()
    (path / "run.launch").write_text("<launch/>\n")
    if owners is not None:
        (path / run_folders.OWNERS).write_text(json.dumps(owners))
    return path


def dead_pid():
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def test_folders_of_dead_owners_are_swept_the_others_kept(tmp_path, monkeypatch):
    monkeypatch.delenv(run_folders.KEEP_RUNS, raising=False)
    me = isolation.process_identity(os.getpid())
    dead = [dead_pid(), 1]
    reused = [os.getpid(), me[1] + 1]          # this pid, but another process's start time
    folder(tmp_path, "evc-x-1-dead", [dead, reused])
    folder(tmp_path, "evc-x-2-live", [dead, me])
    folder(tmp_path, "evc-x-3-unowned", None)  # being made, or made before owners.json
    folder(tmp_path, "other-dead", [dead])     # not a run folder
    removed = run_folders.sweep_stale(str(tmp_path))
    assert removed == [str(tmp_path / "evc-x-1-dead")]
    assert sorted(os.listdir(tmp_path)) == ["evc-x-2-live", "evc-x-3-unowned", "other-dead"]


def test_keep_runs_keeps_every_folder(tmp_path, monkeypatch):
    monkeypatch.setenv(run_folders.KEEP_RUNS, "1")
    folder(tmp_path, "evc-x-1-dead", [[dead_pid(), 1]])
    assert run_folders.sweep_stale(str(tmp_path)) == []
    assert os.listdir(tmp_path) == ["evc-x-1-dead"]


def test_a_made_folder_is_owned_by_its_maker_and_kept(monkeypatch):
    monkeypatch.delenv(run_folders.KEEP_RUNS, raising=False)
    run_dir = run_folders.make("unit", "key")
    try:
        with open(os.path.join(run_dir, run_folders.OWNERS)) as f:
            assert json.load(f) == [isolation.process_identity(os.getpid())]
        assert run_dir not in run_folders.sweep_stale(os.path.dirname(run_dir))
        assert os.path.isdir(run_dir)
    finally:
        subprocess.run(["rm", "-rf", run_dir], check=True)

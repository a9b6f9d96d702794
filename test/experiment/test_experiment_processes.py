"""Processes under stress: a Dask worker killed mid-run, Ctrl-C of the whole experiment, two
experiments side by side, and a separate Dask scheduler and worker. Each ends with every row
ok (or resumable) and, through ``no_process_left``, nothing of the test left running."""
import json
import os
import shutil
import signal

import evc_harness as h
from repo import REPO

DASK = os.path.join(REPO, ".venv", "bin", "dask")
START_GUARD_S = 300             # for the first run to get under way; only against hanging
# once the CLI has exited, its marked processes are already ended (SIGKILL at the latest);
# the grace covers only the kernel finishing a killed process, never a measure of speed
EXITED_GRACE_S = 5.0


def nothing_left(token):
    """Waits (generously) until no process of the test is left; AssertionError naming them."""
    try:
        h.wait_for(lambda: not h.tests_processes(token), 30, "the test's processes to end",
                   poll_s=0.2)
    except AssertionError:
        left = h.tests_processes(token)
        raise AssertionError("still running: " + "; ".join(p.cmdline() for p in left)) \
            from None


def a_run_under_way(token, cli):
    """A shepherd of the CLI's experiment (a run under way) once there is one."""
    found = h.wait_for(lambda: h.shepherds(token) or cli.poll() is not None, START_GUARD_S,
                       "a run to start")
    assert cli.poll() is None, "the experiment ended before any run was seen"
    return found[0]


def test_a_killed_worker_has_its_run_rescheduled(tmp_path, token):
    """kill -9 of the Dask worker whose run is under way: Dask runs that run again elsewhere,
    the CLI exits 0 with 4 ok rows, no key twice; the orphaned shepherd saw its worker gone
    and ended its run early (its shepherd.json says orphaned)."""
    out = tmp_path / "out"
    # the runs' folders kept: the rescheduled run would otherwise sweep the dead one's
    env = h.environment(tmp_path, EVC_KEEP_RUNS=1)
    cli = h.start(h.command(h.fixture("four_runs.yaml"), out, "--workers", 2), tmp_path, env)
    try:
        shepherd = a_run_under_way(token, cli)
        table = h.processes()
        worker = table[shepherd.ppid]
        assert worker.environ().get(h.TOKEN) == token, worker.cmdline()
        assert "spawn_main" in worker.cmdline() or "dask" in worker.cmdline(), worker.cmdline()
        assert worker.pid != cli.pid
        run_dir = shepherd.cmdline().split()[-1]
        os.kill(worker.pid, signal.SIGKILL)
    finally:
        code, stdout, stderr = h.finish(cli)
    assert code == 0, h.explain(code, stdout, stderr)
    rows = h.record(out)
    assert len(rows) == 4, h.describe(rows)
    h.by_key(rows)
    assert {r["status"] for r in rows} == {"ok"}, h.describe(rows)

    # the dead worker cannot remove its run's folder, nor (EVC_KEEP_RUNS) the next run: the
    # shepherd's outcome is still there
    outcome_path = os.path.join(run_dir, "shepherd.json")
    h.wait_for(lambda: os.path.isfile(outcome_path), 60, outcome_path)
    with open(outcome_path) as f:
        outcome = json.load(f)
    shutil.rmtree(run_dir, ignore_errors=True)
    assert outcome["orphaned"] is True, outcome
    assert not outcome["timed_out"], outcome
    nothing_left(token)


def test_ctrl_c_ends_the_experiment_and_the_same_command_resumes(tmp_path, token):
    """SIGINT to the CLI's process group (a terminal's Ctrl-C) once a run is under way: exit
    130, nothing left running, runs.jsonl intact; the same command again completes the
    experiment, every key once, and leaves no run folder behind."""
    out = tmp_path / "out"
    args = h.command(h.fixture("four_runs.yaml"), out, "--workers", 2)
    cli = h.start(args, tmp_path)
    try:
        a_run_under_way(token, cli)
        os.killpg(cli.pid, signal.SIGINT)
    finally:
        code, stdout, stderr = h.finish(cli, timeout_s=300)
    assert code == 130, h.explain(code, stdout, stderr)
    assert "interrupted" in stderr
    # the experiment ends its marked processes before it exits (not merely some time later)
    marked = lambda: [p for p in h.tests_processes(token)  # noqa: E731
                      if p.environ().get("EVC_EXPERIMENT_MARKER")]
    try:
        h.wait_for(lambda: not marked(), EXITED_GRACE_S, "marked processes to be gone")
    except AssertionError:
        raise AssertionError("marked processes outlived the experiment: "
                             + "; ".join(p.cmdline()[:200] for p in marked())) from None
    nothing_left(token)
    before = h.record(out) if (out / "runs.jsonl").exists() else []
    h.by_key(before)
    assert len(before) < 4, "the interrupt came after the end: nothing tested"
    if before:
        assert (out / "runs.jsonl").read_bytes().endswith(b"\n")

    code, stdout, stderr = h.run(args, tmp_path)
    assert code == 0, h.explain(code, stdout, stderr)
    rows = h.record(out)
    assert len(rows) == 4, h.describe(rows)
    h.by_key(rows)
    assert rows[:len(before)] == before
    # the interrupted runs' folders (their workers died with the CLI) are swept by the resume
    assert not list((tmp_path / "tmp").glob("evc-*")), os.listdir(tmp_path / "tmp")
    assert {r["status"] for r in rows} == {"ok"}, h.describe(rows)


def test_two_experiments_side_by_side(tmp_path):
    """Two CLIs at once (one worker each, the same spec, two folders): both exit 0, all ok."""
    spec = h.fixture("wander_speeds.yaml")
    clis = [h.start(h.command(spec, tmp_path / f"out{i}", "--workers", 1, "--seeds", 1),
                    tmp_path) for i in (1, 2)]
    results = [h.finish(cli) for cli in clis]
    for i, (code, stdout, stderr) in enumerate(results, 1):
        assert code == 0, h.explain(code, stdout, stderr)
        rows = h.record(tmp_path / f"out{i}")
        assert len(rows) == 2 and {r["status"] for r in rows} == {"ok"}, h.describe(rows)
    assert set(h.by_key(h.record(tmp_path / "out1"))) == set(h.by_key(h.record(tmp_path / "out2")))


def test_a_separate_scheduler_and_worker(tmp_path, token):
    """``dask scheduler`` and ``dask worker`` as processes of their own; the CLI with
    ``--scheduler``: rows ok, and every run was under that worker (not a local cluster)."""
    env = h.environment(tmp_path)
    scheduler_file = tmp_path / "scheduler.json"
    scheduler = h.start([DASK, "scheduler", "--host", "127.0.0.1", "--port", "0",
                         "--scheduler-file", str(scheduler_file), "--no-dashboard"],
                        tmp_path, env)
    worker = cli = None
    try:
        def address():
            try:
                return json.loads(scheduler_file.read_text())["address"]
            except (OSError, ValueError, KeyError):
                assert scheduler.poll() is None, "the scheduler ended"
                return None
        address = h.wait_for(address, 120, "the scheduler's file")
        worker = h.start([DASK, "worker", "--scheduler-file", str(scheduler_file),
                          "--nthreads", "1", "--nworkers", "1", "--no-dashboard"],
                         tmp_path, env)
        out = tmp_path / "out"
        cli = h.start(h.command(h.fixture("wander_speeds.yaml"), out, "--scheduler", address,
                                "--seeds", 1), tmp_path, env)
        under = {}

        def watch():
            table = h.processes()
            for p in h.shepherds(token):
                under[p.ident] = h.ancestors(p.pid, table)
            return cli.poll() is not None
        h.wait_for(watch, h.CLI_TIMEOUT_S, "the CLI to end", poll_s=0.2)
        code, stdout, stderr = h.finish(cli)
        cli = None
        assert code == 0, h.explain(code, stdout, stderr)
        rows = h.record(out)
        assert len(rows) == 2 and {r["status"] for r in rows} == {"ok"}, h.describe(rows)
        assert under, "no run was seen under way"
        assert all(worker.pid in chain for chain in under.values()), \
            f"runs not under the dask worker {worker.pid}: {under}"
    finally:
        for proc in (cli, worker, scheduler):      # the CLI only when an assertion failed
            if proc is not None:
                h.stop(proc, signal.SIGINT if proc is cli else signal.SIGTERM)
    nothing_left(token)

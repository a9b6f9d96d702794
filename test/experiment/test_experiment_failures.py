"""Failures are data: a node that crashes, one that never publishes what the pace waits for,
and a run that cannot finish in time each become a failed row (retried once first), the
experiment goes on and exits 1, and nothing of theirs is left running."""
import re
import time

import evc_harness as h

MODE = "param.misbehave.mode"
# after its shepherd has exited, a run's processes must be gone: the shepherd waits for its
# descendants and reaps them before it exits; this grace covers only a marked process outside
# its tree, killed but not yet dead (never a measure of speed)
GONE_GRACE_S = 3.0


def test_crashing_and_silent_code_are_failed_rows(tmp_path):
    """evc_fixture_nodes/misbehave (found through the spec's package_path): crash -> failed,
    naming the node and its exit code 3, retried once, with its log tail; silent -> failed, no
    topic matches; ok -> ok. The CLI exits 1."""
    out = tmp_path / "out"
    code, stdout, stderr = h.run(h.command(h.fixture("misbehave.yaml"), out, "--workers", 2),
                                 tmp_path)
    assert code == 1, h.explain(code, stdout, stderr)
    rows = h.record(out)
    by_mode = {r[MODE]: r for r in rows}
    assert len(rows) == 3 and set(by_mode) == {"crash", "silent", "ok"}, h.describe(rows)

    crash = by_mode["crash"]
    assert crash["status"] == "failed", h.describe([crash])
    assert re.fullmatch(r"misbehave(-\d+)? died with exit code 3", crash["error"]), \
        crash["error"]
    assert crash["attempts"] == 2
    assert crash["log_tail"].strip(), "no log tail"
    assert "misbehave" in crash["log_tail"]

    silent = by_mode["silent"]
    assert silent["status"] == "failed"
    assert "no topic matches" in silent["error"] and "/evc/answer" in silent["error"], \
        silent["error"]
    assert silent["attempts"] == 2
    assert silent["log_tail"].strip()

    ok = by_mode["ok"]
    assert ok["status"] == "ok" and ok["attempts"] == 1 and not ok["error"], \
        h.describe([ok]) + "\n" + stderr[-3000:]       # (the CLI says why an attempt failed)
    assert ok["late_steps"] == 0, h.describe([ok])

    # the tables and the report have the failed rows too
    assert {r["status"] for r in h.csv_rows(out)} == {"ok", "failed"}
    assert len(h.parquet_rows(out)) == 3
    assert (out / "report.md").is_file()


def test_a_hanging_run_is_ended_by_its_time_out(tmp_path, token):
    """3000 s of simulated time with 8 s of wall time allowed: a failed row, 'timed out',
    roslaunch's exit status recorded, retried once; the CLI exits 1. The shepherd's clean-up:
    once a run's shepherd has exited, none of that run's processes (its run marker) is left,
    watched while the experiment still runs (its final sweep would hide a shepherd that
    leaves them); and nothing at all is left at the end (no_process_left)."""
    out = tmp_path / "out"
    cli = h.start(h.command(h.fixture("hang.yaml"), out, "--workers", 1), tmp_path)
    watch = RunWatch(token)
    h.wait_for(lambda: watch.poll() or cli.poll() is not None, h.CLI_TIMEOUT_S,
               "the CLI to end", poll_s=0.2)
    code, stdout, stderr = h.finish(cli)
    assert code == 1, h.explain(code, stdout, stderr)
    # the first attempt's shepherd ended while the experiment went on (the retry), so what
    # ended its run's processes was the shepherd, not the experiment's final sweep
    assert len(watch.shepherds) == 2, watch.shepherds
    assert watch.ended_while_running, "no shepherd was seen ending before the experiment"
    assert not watch.leftovers, f"a run's processes outlived its shepherd: {watch.leftovers}"
    rows = h.record(out)
    assert len(rows) == 1, h.describe(rows)
    row = rows[0]
    assert row["status"] == "failed" and "timed out" in row["error"], h.describe(rows)
    assert row["attempts"] == 2
    assert isinstance(row["exit_code"], int), h.describe(rows)
    assert row["log_tail"].strip()


class RunWatch:
    """The test's processes by run (``EVC_RUN_MARKER``), polled while an experiment runs:
    each run's shepherd, the runs whose shepherd ended while the experiment went on, and
    processes of a run still alive ``GONE_GRACE_S`` after its shepherd ended."""

    def __init__(self, token):
        self.token = token
        self.shepherds = {}            # run marker -> the shepherd's (pid, start time)
        self.gone_at = {}              # run marker -> when its shepherd was first seen gone
        self.ended_while_running = set()
        self.leftovers = {}

    def poll(self):
        by_run = {}
        for p in h.tests_processes(self.token):
            marker = p.environ().get("EVC_RUN_MARKER")
            if marker:
                by_run.setdefault(marker, []).append(p)
                if "epuck_vrep_compat.experiment.shepherd" in p.cmdline():
                    self.shepherds[marker] = p.ident
        now = time.monotonic()
        for marker, shepherd in self.shepherds.items():
            procs = by_run.get(marker, [])
            if shepherd in {p.ident for p in procs}:
                continue
            self.ended_while_running.add(marker)
            since = self.gone_at.setdefault(marker, now)
            if procs and now - since > GONE_GRACE_S:
                self.leftovers[marker] = [p.cmdline()[:200] for p in procs]
        return False

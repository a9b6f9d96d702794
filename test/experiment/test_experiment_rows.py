"""An experiment through its CLI, as a user runs it: rows, tables, report and plots; the same
row from the same run; a resumed experiment runs only what it lacks; a bad spec runs nothing."""
import math
import os

import evc_harness as h

SPEEDS = (0.02, 0.08)
SPEED = "param.wander.speed_m_s"


def test_rows_tables_report_and_no_marked_process_left(tmp_path, token):
    """4 runs (2 speeds x 2 seeds, 3 s each) on 2 workers: exit 0, one ok row per run in
    results.csv and results.parquet with the parameter and metric columns, the faster wander
    drives farther, summary, report and PNG plots exist; and while it ran its processes carried
    the experiment's marker, none of which is left once the CLI has exited."""
    out = tmp_path / "out"
    cli = h.start(h.command(h.fixture("wander_speeds.yaml"), out, "--workers", 2), tmp_path)
    markers = set()

    def marked_processes():
        for p in h.tests_processes(token):
            marker = p.environ().get("EVC_EXPERIMENT_MARKER")
            if marker:
                markers.add(marker)
        return cli.poll() is not None

    h.wait_for(marked_processes, h.CLI_TIMEOUT_S, "the CLI to end", poll_s=0.5)
    code, stdout, stderr = h.finish(cli)
    assert code == 0, h.explain(code, stdout, stderr)

    # its runs' processes carried the experiment's marker; none is left (whoever's it is)
    assert len(markers) == 1, f"experiment markers seen while it ran: {markers}"
    marker = markers.pop()
    left = [p for p in h.processes().values()
            if p.alive and p.environ().get("EVC_EXPERIMENT_MARKER") == marker]
    assert not left, "marked processes left: " + "; ".join(p.cmdline() for p in left)

    for rows in (h.csv_rows(out), h.parquet_rows(out)):
        assert len(rows) == 4, h.describe(rows)
        h.by_key(rows)
        for column in ("run_key", "status", "seed", "attempts", "wall_s", "cpu_s", "exit_code",
                       "late_steps", "host", "error", SPEED, "metric.distance_driven_m",
                       "metric.collisions", "metric.coverage"):
            assert all(column in r for r in rows), f"no column {column}: {sorted(rows[0])}"
        assert {r["status"] for r in rows} == {"ok"}, h.describe(rows)
        assert sorted((float(r[SPEED]), int(r["seed"])) for r in rows) == \
            [(SPEEDS[0], 0), (SPEEDS[0], 1), (SPEEDS[1], 0), (SPEEDS[1], 1)]
        distance = {(float(r[SPEED]), int(r["seed"])): float(r["metric.distance_driven_m"])
                    for r in rows}
        assert all(d > 0 and math.isfinite(d) for d in distance.values()), distance
        for seed in (0, 1):
            assert distance[(SPEEDS[1], seed)] > distance[(SPEEDS[0], seed)], distance
        for r in rows:
            assert 0.0 <= float(r["metric.coverage"]) <= 1.0
            assert float(r["metric.collisions"]) >= 0
            # the CPU time of the run's processes: the simulator and the nodes did work
            assert float(r["cpu_s"]) > 0.0, h.describe([r])
    # the two tables are the same rows
    parquet = {r["run_key"]: r for r in h.parquet_rows(out)}
    for r in h.csv_rows(out):
        assert float(r["metric.distance_driven_m"]) == \
            parquet[r["run_key"]]["metric.distance_driven_m"]

    summary = (out / "summary.csv").read_text()
    assert "distance_driven_m" in summary and len(summary.splitlines()) >= 3, summary
    report = (out / "report.md").read_text()
    assert "wander_speeds" in report and "distance_driven_m" in report
    pngs = sorted(out.glob("*.png"))
    assert any("distance_driven_m" in p.name for p in pngs), pngs
    for png in pngs:
        with open(png, "rb") as f:
            assert f.read(8) == h.PNG_SIGNATURE, png


def test_the_same_run_gives_the_same_row(tmp_path):
    """The spec's first seed (2 runs) into two folders: the same run keys, and every metric of
    every run exactly equal (lock-step with a node that answers each step once)."""
    rows = []
    for name in ("first", "second"):
        code, stdout, stderr = h.run(h.command(h.fixture("wander_speeds.yaml"),
                                               tmp_path / name, "--workers", 2, "--seeds", 1),
                                     tmp_path)
        assert code == 0, h.explain(code, stdout, stderr)
        rows.append(h.by_key(h.record(tmp_path / name)))
    first, second = rows
    assert len(first) == 2 and set(first) == set(second)
    for key in first:
        assert first[key]["status"] == second[key]["status"] == "ok"
        m1, m2 = h.metrics_of(first[key]), h.metrics_of(second[key])
        assert m1 and m1 == m2, f"run {key} differs:\n{m1}\n{m2}"


def test_resume_runs_only_the_missing_seeds(tmp_path):
    """seeds: 3 run with --seeds 2 (4 rows), then in full: 6 rows, no key twice, the first
    four untouched and the second call ran only the third seed's 2 runs."""
    spec, out = h.fixture("resume.yaml"), tmp_path / "out"
    code, stdout, stderr = h.run(h.command(spec, out, "--workers", 2, "--seeds", 2), tmp_path)
    assert code == 0, h.explain(code, stdout, stderr)
    first = h.record(out)
    assert len(first) == 4 and {r["seed"] for r in first} == {0, 1}, h.describe(first)
    with open(out / "runs.jsonl") as f:
        first_text = f.read()

    code, stdout, stderr = h.run(h.command(spec, out, "--workers", 2), tmp_path)
    assert code == 0, h.explain(code, stdout, stderr)
    assert "6 run(s), 4 already in" in stderr, stderr
    assert stderr.count("experiment: run ") == 2, stderr        # one progress line per run
    rows = h.record(out)
    assert len(rows) == 6, h.describe(rows)
    h.by_key(rows)
    with open(out / "runs.jsonl") as f:
        assert f.read().startswith(first_text)
    assert sorted(r["seed"] for r in rows[4:]) == [2, 2], h.describe(rows)
    assert {r["status"] for r in rows} == {"ok"}
    assert len(h.csv_rows(out)) == 6 and len(h.parquet_rows(out)) == 6


def test_a_bad_spec_exits_2_naming_its_key_and_line(tmp_path):
    """An unknown simulator argument: exit status 2, the key and its line on stderr, and
    nothing ran (no results folder)."""
    out = tmp_path / "out"
    code, stdout, stderr = h.run(h.command(h.fixture("bad.yaml"), out, "--workers", 1),
                                 tmp_path)
    assert code == 2, h.explain(code, stdout, stderr)
    assert "line 6" in stderr and "simulator.args.not_an_arg" in stderr, stderr
    assert not out.exists() or not os.listdir(out), os.listdir(out)
    assert not (tmp_path / "results").exists()

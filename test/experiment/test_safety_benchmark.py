"""The safety benchmark (experiments/safety_ssm.yaml through ``safety_bench``) at a small size:
every monitor x fault cell over one walk and our supervisor over two, all ok, with the
results the arithmetic predicts for that walk; and the coverage maps of both layouts."""
import os

import evc_harness as h


def test_every_cell_one_walk_and_the_report(tmp_path):
    """12 runs (11 cells x seed 0, and seed 1 of ssm at its defaults without a fault). Without
    a monitor the arm stays in the operator's S_p for seconds; our supervisor cuts that time;
    killed or fed a frozen estimate it leaves the arm stopped (the watchdog, the fail-safe);
    report.md holds the table and each monitor's worst walk as a replay command."""
    out = tmp_path / "out"
    code, stdout, stderr = h.run(["rosrun", "epuck_vrep_compat", "safety_bench", "run", "--out",
                                  str(out), "--walks", "2", "--cell-walks", "1", "--workers",
                                  "2", "--no-coverage"], tmp_path)
    assert code == 0, h.explain(code, stdout, stderr)
    rows = h.record(out / "walks")
    h.by_key(rows)
    assert len(rows) == 12 and {r["status"] for r in rows} == {"ok"}, h.describe(rows)

    def cell(monitor, fault="none", seed=0):
        """The row of that monitor at its defaults (no monitor.* parameter varied)."""
        chosen = [r for r in rows if r["param.monitor.monitor"] == monitor and r["seed"] == seed
                  and r["param.fault.fault"] == fault
                  and not any(k.startswith("param.monitor.") and k != "param.monitor.monitor"
                              for k in r)]
        assert len(chosen) == 1, h.describe(rows)
        return chosen[0]
    none, ssm = cell("none"), cell("ssm")
    assert none["metric.violation_s"] > 0.5, h.describe([none])
    assert ssm["metric.violation_s"] < none["metric.violation_s"], h.describe([ssm, none])
    assert none["metric.productivity"] == 1.0 and ssm["metric.productivity"] < 1.0
    for fault in ("monitor_killed", "tracker_frozen"):
        row = cell("ssm", fault)
        assert row["metric.final_scale"] == 0.0, h.describe([row])
    report = (out / "report.md").read_text()
    assert "| ssm | none | 2 |" in report, report
    assert "roslaunch ssm_bench replay.launch seed:=" in report, report


def test_coverage_maps_of_both_layouts(tmp_path):
    """The lawnmower walk in the thesis's layout and the alternative: a PNG each; the thesis's
    ceiling cameras leave the floor's south strip unseen, where the tracker coasts off, and the
    alternative (camera 0 moved over it) tracks him there: a smaller mean error."""
    code, stdout, stderr = h.run(["rosrun", "epuck_vrep_compat", "safety_bench", "coverage",
                                  str(tmp_path / "out")], tmp_path)
    assert code == 0, h.explain(code, stdout, stderr)
    for layout in ("thesis", "alternative"):
        path = tmp_path / "out" / f"coverage_{layout}.png"
        assert path.is_file() and os.path.getsize(path) > 10000, stdout
    rows = h.record(tmp_path / "out" / "coverage")
    assert {r["status"] for r in rows} == {"ok"}, h.describe(rows)
    error = {os.path.basename(r["param.sim.world"]).split("_")[0]: r["metric.tracker_error_mean_m"]
             for r in rows}
    assert 0.0 < error["alternative"] < error["thesis"], error

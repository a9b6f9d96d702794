"""The experiment report: Student's t quantiles against the tables, the per-cell summary
against hand-computed values, and a report written into a temporary folder (its CSV, valid
PNGs, and a report.md with the failed runs and the reference verdicts), the same every time."""
import math
import warnings

import pytest

from epuck_vrep_compat.experiment import report
from epuck_vrep_compat.experiment.report import summarize, t_quantile, write_report

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("p, df, expected", [
    (0.975, 1, 12.706), (0.975, 2, 4.303), (0.975, 9, 2.262), (0.975, 29, 2.045),
    (0.975, 30, 2.042), (0.975, 120, 1.980), (0.995, 4, 4.604), (0.95, 10, 1.812),
    (0.975, 5000, 1.9604), (0.975, 10 ** 7, 1.95996)])
def test_t_quantiles_match_the_tables(p, df, expected):
    assert t_quantile(p, df) == pytest.approx(expected, abs=6e-4 if df < 1000 else 6e-5)


def test_t_quantile_is_exact_where_it_has_a_closed_form():
    assert t_quantile(0.975, 1) == pytest.approx(math.tan(math.pi * 0.475), rel=1e-10)
    assert t_quantile(0.975, 2) == pytest.approx(0.95 / math.sqrt(2 * 0.975 * 0.025),
                                                 rel=1e-10)


@pytest.mark.parametrize("df", [1001, 5000])
def test_the_large_df_series_agrees_with_the_exact_distribution(df):
    # the series' next term is below 1e-11 in t at df > 1000
    for p in (0.95, 0.975, 0.995):
        assert report._t_two_sided(t_quantile(p, df), df) == pytest.approx(2 * p - 1, abs=5e-11)


@pytest.mark.parametrize("p, df", [(0.5, 3), (1.0, 3), (0.975, 0)])
def test_t_quantile_refuses_what_it_cannot_answer(p, df):
    with pytest.raises(ValueError):
        t_quantile(p, df)


def run(key, speed, preset, seed, value, status="ok", error=None):
    row = {"run_key": key, "seed": seed, "status": status, "attempts": 1, "wall_s": 2.0,
           "param.speed": speed, "param.preset": preset, "param.n": 2}
    if status == "ok":
        row["metric.dist"] = value
        row["metric.hits"] = float(seed % 2)
    else:
        row["error"] = error
    return row


def rows_of_an_experiment():
    """speed 10 and 9 (numbers: 9 sorts first), preset a and b; dist is 1, 2, 3 for
    (9, a), 4, 4, nan for (10, a); (9, b) has 5, 7 and a failed run; (10, b) only fails."""
    return [run("r00", 9, "a", 0, 1.0), run("r01", 9, "a", 1, 2.0), run("r02", 9, "a", 2, 3.0),
            run("r03", 10, "a", 0, 4.0), run("r04", 10, "a", 1, 4.0),
            run("r05", 10, "a", 2, math.nan),
            run("r06", 9, "b", 0, 5.0), run("r07", 9, "b", 1, 7.0),
            run("r08", 9, "b", 2, None, "failed", "Timeout: no clock\nTraceback ..."),
            run("r09", 10, "b", 0, None, "failed", "roslaunch | exit 1")]


def test_summary_per_cell_against_hand_computed_values():
    summary = summarize(rows_of_an_experiment(), ["speed", "preset"], ["dist", "hits"])
    dist = [e for e in summary if e["metric"] == "dist"]
    assert [(e["param.speed"], e["param.preset"]) for e in dist] == [
        (9, "a"), (9, "b"), (10, "a"), (10, "b")]
    a9, b9, a10, b10 = dist
    # 1, 2, 3: mean 2, SD 1, half width t(0.975, 2) / sqrt(3) = 4.3027 / 1.7321 = 2.4841
    assert (a9["n"], a9["mean"], a9["sd"], a9["n_failed"]) == (3, 2.0, 1.0, 0)
    assert (a9["ci95_low"], a9["ci95_high"]) == pytest.approx((2 - 2.48414, 2 + 2.48414),
                                                              abs=1e-5)
    # 5, 7: mean 6, SD sqrt(2), half width 12.7062 * sqrt(2) / sqrt(2) = 12.7062; one failed
    assert (b9["n"], b9["mean"], b9["n_failed"]) == (2, 6.0, 1)
    assert b9["sd"] == pytest.approx(math.sqrt(2))
    assert b9["ci95_high"] == pytest.approx(6 + 12.70620, abs=1e-5)
    # 4, 4 and an undefined value: SD 0, an interval of zero width
    assert (a10["n"], a10["n_undefined"], a10["mean"], a10["sd"]) == (2, 1, 4.0, 0.0)
    assert (a10["ci95_low"], a10["ci95_high"]) == (4.0, 4.0)
    # nothing ran: no numbers, two failures counted once each per metric
    assert (b10["n"], b10["n_failed"]) == (0, 1) and math.isnan(b10["mean"])
    assert math.isnan(b10["ci95_low"])
    hits = [e for e in summary if e["metric"] == "hits"]
    assert [e["mean"] for e in hits[:1]] == [pytest.approx(1 / 3)]


def test_one_run_has_a_mean_but_no_spread():
    (entry,) = summarize([run("r", 1, "a", 0, 2.5)], ["speed"], ["dist"])
    assert entry["mean"] == 2.5 and math.isnan(entry["sd"]) and math.isnan(entry["ci95_low"])


SPEC_INFO = {"name": "wander_speed", "spec_hash": "0123abcd", "params": ["speed", "preset", "n"],
             "metrics": ["dist", "hits"], "reference": {"dist": 2.5},
             "description": "How far the wanderer gets."}


def test_report_files_plots_and_reference_verdicts(tmp_path):
    written = write_report(str(tmp_path), rows_of_an_experiment(), SPEC_INFO)
    assert written == ["summary.csv", "dist_vs_speed.png", "dist_vs_preset.png",
                       "dist_seeds.png", "hits_vs_speed.png", "hits_vs_preset.png",
                       "hits_seeds.png", "report.md"]
    for name in written:
        assert (tmp_path / name).stat().st_size > 0
        if name.endswith(".png"):
            assert (tmp_path / name).read_bytes()[:8] == PNG_SIGNATURE
    md = (tmp_path / "report.md").read_text()
    for text in ("# Experiment wander_speed", "`0123abcd`", "How far the wanderer gets.",
                 "10 (8 ok, 2 failed)", "| r08 | 2 | 1 | Timeout: no clock |",
                 "| r09 | 0 | 1 | roslaunch \\| exit 1 |", "- varied: speed, preset",
                 "- fixed: n = 2", "![dist against speed](dist_vs_speed.png)"):
        assert text in md, text
    assert "Traceback" not in md
    # 2.5 lies in (9, a)'s [-0.48, 4.48] and (9, b)'s [-6.7, 18.7], not in (10, a)'s [4, 4]
    assert "| 9 | a | dist | 3 | 2 | 1 | [-0.4841, 4.484] | 0 | 2.5 | yes |" in md
    assert "| 9 | b | dist | 2 | 6 | 1.414 | [-6.706, 18.71] | 1 | 2.5 | yes |" in md
    assert "| 10 | a | dist | 2 (+1 NaN) | 4 | 0 | [4, 4] | 0 | 2.5 | no |" in md
    assert "| 10 | b | dist | 0 | — | — | [—, —] | 1 | 2.5 | n/a |" in md
    csv_lines = (tmp_path / "summary.csv").read_text().splitlines()
    assert csv_lines[0] == ("param.speed,param.preset,param.n,metric,n,n_undefined,mean,sd,"
                            "ci95_low,ci95_high,n_failed,reference,reference_in_ci95")
    assert csv_lines[5] == "10,a,2,dist,2,1,4.0,0.0,4.0,4.0,0,2.5,no"


def test_the_report_is_the_same_every_time(tmp_path):
    rows = rows_of_an_experiment()
    write_report(str(tmp_path / "one"), rows, SPEC_INFO)
    write_report(str(tmp_path / "two"), list(reversed(rows)), SPEC_INFO)
    for name in ("report.md", "summary.csv"):
        assert (tmp_path / "one" / name).read_bytes() == (tmp_path / "two" / name).read_bytes()


def test_many_cells_pool_the_other_parameters(tmp_path):
    rows = [run(f"r{i}{j}", i, f"p{j}", 0, float(i + j)) for i in range(3) for j in range(8)]
    info = dict(SPEC_INFO, reference={}, metrics=None)     # metrics: the rows' columns
    written = write_report(str(tmp_path), rows, info)
    assert "dist_vs_preset.png" in written and "reference" not in \
        (tmp_path / "summary.csv").read_text().splitlines()[0]
    assert "in interval" not in (tmp_path / "report.md").read_text()


def test_list_valued_parameters_make_cells_and_csv_cells(tmp_path):
    rows = [dict(run(f"r{i}", 1, "a", i, float(i)), **{"param.start": start})
            for i, start in enumerate([[0.1, 0.0], [0.1, 0.0], [-0.2, 0.0]])]
    summary = summarize(rows, ["start"], ["dist"])
    assert [(e["param.start"], e["n"]) for e in summary] == [([-0.2, 0.0], 1), ([0.1, 0.0], 2)]
    write_report(str(tmp_path), rows, dict(SPEC_INFO, params=["start"]))
    assert (tmp_path / "summary.csv").read_text().splitlines()[1].startswith('"[-0.2, 0.0]",dist')


def test_a_report_of_runs_that_all_failed(tmp_path):
    rows = [run(f"r{i}", speed, "a", 0, None, "failed", "no clock") for i, speed in
            enumerate([1, 2])]
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no plotting of empty data
        written = write_report(str(tmp_path), rows, dict(SPEC_INFO, metrics=["dist"]))
    assert written == ["summary.csv", "dist_vs_speed.png", "dist_seeds.png", "report.md"]
    assert "2 (0 ok, 2 failed)" in (tmp_path / "report.md").read_text()

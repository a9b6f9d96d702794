"""The experiment's summary and report: per parameter cell and metric, the number of runs, the
mean, the SD and a 95 % interval for the mean (Student's t), written as ``summary.csv``, PNG
figures (``report_plots``) and ``report.md``.

A row is one run: ``run_key``, ``seed``, ``status`` (``ok`` or anything else: failed),
``attempts``, ``wall_s``, ``error`` (failed runs: the message), ``param.<name>`` and
``metric.<name>``. A cell is one combination of parameter values. Only ok runs' finite
values count for a metric (``n``); ok runs whose value is NaN (e.g. a region never reached)
are counted apart (``n_undefined``). Output is deterministic: cells sorted by their values.
"""
import csv
import json
import math
import os
import re
from statistics import NormalDist

import numpy as np

from epuck_vrep_compat.experiment import report_plots
from epuck_vrep_compat.experiment.report_plots import MAX_SERIES, as_number, label, value_order

SUMMARY_COLUMNS = ("metric", "n", "n_undefined", "mean", "sd", "ci95_low", "ci95_high",
                   "n_failed")
EXACT_T_MAX_DF = 1000       # above: the Cornish-Fisher series, off by < 1e-9 there


def _t_two_sided(t, df):
    """P(|T| <= t) for Student's T with integer ``df`` (Abramowitz & Stegun 26.7.3-4)."""
    theta = math.atan(t / math.sqrt(df))
    c2, total = math.cos(theta) ** 2, 0.0
    if df % 2:
        term = math.cos(theta)
        for k in range(1, (df - 1) // 2 + 1):
            total += term
            term *= c2 * (2 * k) / (2 * k + 1)
        return 2.0 / math.pi * (theta + math.sin(theta) * total)
    term = 1.0
    for k in range(1, df // 2 + 1):
        total += term
        term *= c2 * (2 * k - 1) / (2 * k)
    return math.sin(theta) * total


def t_quantile(p: float, df: int) -> float:
    """The ``p`` quantile (0.5 < p < 1) of Student's t with ``df`` >= 1 degrees of freedom:
    the exact distribution function solved by bisection, a normal series for large ``df``."""
    if not 0.5 < p < 1.0 or df < 1:
        raise ValueError(f"t_quantile needs 0.5 < p < 1 and df >= 1, got p={p}, df={df}")
    df = int(df)
    if df > EXACT_T_MAX_DF:
        z = NormalDist().inv_cdf(p)
        return (z + (z ** 3 + z) / (4 * df) + (5 * z ** 5 + 16 * z ** 3 + 3 * z) / (96 * df ** 2)
                + (3 * z ** 7 + 19 * z ** 5 + 17 * z ** 3 - 15 * z) / (384 * df ** 3))
    target, lo, hi = 2.0 * p - 1.0, 0.0, 1.0
    while _t_two_sided(hi, df) < target:
        lo, hi = hi, 2.0 * hi
    while hi - lo > 1e-12 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _t_two_sided(mid, df) < target else (lo, mid)
    return 0.5 * (lo + hi)


def _hashable(v):
    if isinstance(v, (list, tuple)):
        return tuple(_hashable(x) for x in v)
    if isinstance(v, dict):
        return tuple(sorted((k, _hashable(x)) for k, x in v.items()))
    return v


def _cells(rows, param_names):
    """{cell key: (parameter values, ok rows, failed count)} in sorted order."""
    cells = {}
    for row in rows:
        values = tuple(row.get(f"param.{p}") for p in param_names)
        cell = cells.setdefault(tuple(_hashable(v) for v in values), [values, [], 0])
        if row.get("status") == "ok":
            cell[1].append(row)
        else:
            cell[2] += 1
    return [cells[k] for k in sorted(cells, key=lambda k: [value_order(v) for v in k])]


def summarize(rows, param_names, metric_names) -> list:
    """One dict per cell and metric, cells in sorted order, metrics in the given order:
    ``param.<name>`` (the cell's values), ``metric``, ``n`` (ok runs with a finite value),
    ``n_undefined``, ``mean``, ``sd`` (ddof 1), ``ci95_low``/``ci95_high`` (mean ± t(0.975,
    n−1)·sd/√n), ``n_failed`` (the cell's failed runs). NaN where n is too small."""
    out = []
    for values, ok, failed in _cells(rows, param_names):
        for metric in metric_names:
            x = np.array([as_number(r.get(f"metric.{metric}")) for r in ok], dtype=float)
            finite = x[np.isfinite(x)]
            n = int(finite.size)
            mean = float(finite.mean()) if n else math.nan
            sd = float(finite.std(ddof=1)) if n > 1 else math.nan
            half = t_quantile(0.975, n - 1) * sd / math.sqrt(n) if n > 1 else math.nan
            entry = {f"param.{p}": v for p, v in zip(param_names, values)}
            entry.update(metric=metric, n=n, n_undefined=int(x.size - n), mean=mean, sd=sd,
                         ci95_low=mean - half, ci95_high=mean + half, n_failed=failed)
            out.append(entry)
    return out


def verdict(entry, reference) -> str:
    """Whether a summary entry's 95 % interval contains ``reference``: yes, no, or n/a (no
    reference, or too few runs for an interval)."""
    if reference is None or math.isnan(entry["ci95_low"]):
        return "n/a"
    return "yes" if entry["ci95_low"] <= reference <= entry["ci95_high"] else "no"


def _metric_names(rows, declared):
    """The declared metric columns the rows hold, in their order, then the others the rows
    hold, sorted (all declared ones when no row holds any, e.g. every run failed)."""
    found = {k[len("metric."):] for row in rows for k in row if k.startswith("metric.")}
    if not found:
        return list(declared)
    return [m for m in declared if m in found] + sorted(found - set(declared))


def _safe(name):
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def _cell_text(v):
    if isinstance(v, float):
        return repr(v)
    return json.dumps(v) if isinstance(v, (list, dict)) else str(v)


def write_report(out_dir, rows, spec_info) -> list:
    """Writes ``summary.csv``, the figures and ``report.md`` into ``out_dir`` (created if
    needed); returns the names of the files written. ``spec_info``: ``name``, ``spec_hash``,
    ``params`` (names), ``metrics`` (metric column names), optional ``reference``
    ({metric: value}, e.g. a real robot's figure) and ``description``."""
    os.makedirs(out_dir, exist_ok=True)
    params = list(spec_info.get("params") or [])
    metrics = _metric_names(rows, list(spec_info.get("metrics") or []))
    reference = dict(spec_info.get("reference") or {})
    summary = summarize(rows, params, metrics)
    varied = [p for p in params
              if len({_hashable(r.get(f"param.{p}")) for r in rows}) > 1]
    written = [_write_csv(os.path.join(out_dir, "summary.csv"), summary, params, reference)]
    figures = {m: _figures(out_dir, rows, summary, m, varied) for m in metrics}
    lines = _markdown(rows, spec_info, params, varied, summary, reference, figures)
    with open(os.path.join(out_dir, "report.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    return written + [name for m in metrics for name, _caption in figures[m]] + ["report.md"]


def _write_csv(path, summary, params, reference):
    header = [f"param.{p}" for p in params] + list(SUMMARY_COLUMNS)
    if reference:
        header += ["reference", "reference_in_ci95"]
    with open(path, "w", encoding="utf-8", newline="") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(header)
        for entry in summary:
            ref = reference.get(entry["metric"])
            row = [_cell_text(entry[k]) for k in header[:len(params) + len(SUMMARY_COLUMNS)]]
            if reference:
                row += ["" if ref is None else repr(float(ref)), verdict(entry, ref)]
            writer.writerow(row)
    return os.path.basename(path)


def _figures(out_dir, rows, summary, metric, varied):
    """(file, caption) of one figure per varied parameter (one line per combination of the
    others when there are few, else the runs pooled over them) and of the per-seed scatter."""
    figures = []
    for p in varied:
        others = [q for q in varied if q != p]
        combos = {tuple(_hashable(e[f"param.{q}"]) for q in others) for e in summary}
        path = os.path.join(out_dir, f"{_safe(metric)}_vs_{_safe(p)}.png")
        if len(combos) <= MAX_SERIES:
            name = report_plots.plot_against(path, summary, metric, p, others)
        else:
            pooled = summarize(rows, [p], [metric])
            name = report_plots.plot_against(path, pooled, metric, p, (),
                                             f" (pooled over {', '.join(others)})")
        figures.append((name, f"{metric} against {p}"))
    path = os.path.join(out_dir, f"{_safe(metric)}_seeds.png")
    figures.append((report_plots.plot_seeds(path, rows, metric, varied), f"{metric} per seed"))
    return figures


def _number_text(v) -> str:
    return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else f"{v:.4g}"


def _markdown(rows, spec_info, params, varied, summary, reference, figures):
    ok = [r for r in rows if r.get("status") == "ok"]
    failed = [r for r in rows if r.get("status") != "ok"]
    lines = [f"# Experiment {spec_info.get('name', '')}", ""]
    if spec_info.get("description"):
        lines += [str(spec_info["description"]).strip(), ""]
    lines += [f"- spec hash: `{spec_info.get('spec_hash', '')}`",
              f"- runs: {len(rows)} ({len(ok)} ok, {len(failed)} failed)",
              f"- varied: {', '.join(varied) or 'nothing'}"]
    fixed = [p for p in params if p not in varied and rows]
    if fixed:
        lines.append("- fixed: " + ", ".join(f"{p} = {label(rows[0].get(f'param.{p}'))}"
                                               for p in fixed))
    if failed:
        lines += ["", "## Failed runs", "", "| run | seed | attempts | error |",
                  "| --- | --- | --- | --- |"]
        for r in sorted(failed, key=lambda r: str(r.get("run_key", ""))):
            error = (str(r.get("error") or "").strip().splitlines() or [""])[0]
            error = error.replace("|", "\\|")          # a bar would end the table's cell
            lines.append(f"| {r.get('run_key', '')} | {r.get('seed', '')} | "
                         f"{r.get('attempts', '')} | {error} |")
    lines += ["", "## Summary", "", "Mean, SD and the 95 % interval of the mean (Student's t) "
              "over each cell's ok runs; n counts the runs with a value (NaN: ok runs without one, "
              "e.g. a region never reached).", ""]
    lines += _summary_table(summary, varied, reference)
    lines += ["", "## Figures"]
    for metric, names in figures.items():
        lines += ["", f"### {metric}"]
        for name, caption in names:
            lines += ["", f"![{caption}]({name})"]
    return lines


def _summary_table(summary, varied, reference):
    head = varied + ["metric", "n", "mean", "SD", "95 % interval", "failed"]
    if reference:
        head += ["reference", "in interval"]
    lines = ["| " + " | ".join(head) + " |", "|" + " --- |" * len(head)]
    for e in summary:
        cells = [label(e[f"param.{p}"]) for p in varied] + [
            e["metric"], str(e["n"]) + (f" (+{e['n_undefined']} NaN)" if e["n_undefined"] else ""),
            _number_text(e["mean"]), _number_text(e["sd"]),
            f"[{_number_text(e['ci95_low'])}, {_number_text(e['ci95_high'])}]",
            str(e["n_failed"])]
        if reference:
            ref = reference.get(e["metric"])
            cells += [_number_text(ref), verdict(e, ref) if ref is not None else ""]
        lines.append("| " + " | ".join(cells) + " |")
    return lines

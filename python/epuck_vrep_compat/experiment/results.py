"""An experiment's results folder, written as runs finish so that nothing done is lost.

``runs.jsonl`` is the record: one JSON line per finished run, appended and flushed the moment
the run's row arrives; a resumed experiment reads it and runs only the keys it lacks.
``results.csv`` and ``results.parquet`` are the tidy table (a row per run, a column per
parameter and metric), rewritten from the record after every row. ``spec.json`` keeps the
checked spec so that ``experiment report DIR`` can rebuild everything from the folder alone.
"""
import csv
import json
import math
import os

import pyarrow as pa
import pyarrow.parquet as pq

FIRST_COLUMNS = ("run_key", "status", "seed", "attempts", "wall_s", "startup_s", "stepping_s",
                 "teardown_s", "cpu_s", "exit_code", "late_steps", "host", "error")


class ResultStore:
    """The results folder of one experiment: its record of runs and its tables."""

    def __init__(self, out_dir):
        self.out_dir = out_dir
        os.makedirs(out_dir, exist_ok=True)
        self.record_path = os.path.join(out_dir, "runs.jsonl")
        self.rows = self._read()

    def _read(self):
        rows = []
        if os.path.isfile(self.record_path):
            with open(self.record_path) as f:
                for line in f:
                    line = line.strip()
                    if line:
                        try:
                            rows.append(json.loads(line))
                        except ValueError:
                            continue    # a line cut by a crash mid-write: that run reruns
        return rows

    @property
    def done(self):
        """Keys of the runs already recorded (ok or failed after its retry)."""
        return {r["run_key"] for r in self.rows}

    def add(self, row):
        # after a crash mid-write the record ends mid-line: the new line must start anew
        start = "\n" if _ends_mid_line(self.record_path) else ""
        with open(self.record_path, "a") as f:
            f.write(start + json.dumps(_plain(row), sort_keys=True) + "\n")
            f.flush()
            os.fsync(f.fileno())
        self.rows.append(_plain(row))
        self.write_tables()

    def columns(self):
        names = set().union(*(r.keys() for r in self.rows)) if self.rows else set()
        first = [c for c in FIRST_COLUMNS if c in names]
        params = sorted(c for c in names if c.startswith("param."))
        metric_cols = sorted(c for c in names if c.startswith("metric."))
        rest = sorted(names - set(first) - set(params) - set(metric_cols) - {"log_tail"})
        return first + params + metric_cols + rest + (["log_tail"] if "log_tail" in names
                                                      else [])

    def write_tables(self):
        columns = self.columns()
        tmp = os.path.join(self.out_dir, "results.csv.tmp")
        with open(tmp, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
            writer.writeheader()
            for row in self.rows:
                writer.writerow({c: row.get(c, "") for c in columns})
        os.replace(tmp, os.path.join(self.out_dir, "results.csv"))
        table = pa.table({c: _column(self.rows, c) for c in columns})
        pq.write_table(table, os.path.join(self.out_dir, "results.parquet.tmp"))
        os.replace(os.path.join(self.out_dir, "results.parquet.tmp"),
                   os.path.join(self.out_dir, "results.parquet"))

    def save_spec(self, spec):
        with open(os.path.join(self.out_dir, "spec.json"), "w") as f:
            json.dump(_plain(spec), f, indent=1, sort_keys=True, default=str)

    def load_spec(self):
        with open(os.path.join(self.out_dir, "spec.json")) as f:
            return json.load(f)


def _ends_mid_line(path):
    try:
        with open(path, "rb") as f:
            f.seek(-1, os.SEEK_END)
            return f.read(1) != b"\n"
    except OSError:                     # no record yet, or an empty one
        return False


def _plain(value):
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, set):
        return sorted(_plain(v) for v in value)
    if isinstance(value, float) and not math.isfinite(value):
        return None if math.isnan(value) else value
    if hasattr(value, "item"):          # numpy scalars
        return _plain(value.item())
    return value


def _column(rows, name):
    values = [r.get(name) for r in rows]
    kinds = {type(v) for v in values if v is not None}
    if not kinds:                       # NaN everywhere (a metric of one robot's pairs)
        return pa.array(values, pa.float64())
    if kinds <= {int, float}:
        return pa.array([float(v) if v is not None else None for v in values], pa.float64()) \
            if float in kinds else pa.array(values, pa.int64())
    if kinds == {bool}:
        return pa.array(values, pa.bool_())
    return pa.array([None if v is None else str(v) for v in values], pa.string())

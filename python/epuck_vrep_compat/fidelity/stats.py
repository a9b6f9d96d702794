"""The statistics of the fidelity tools, numpy only: noise fits with standard errors and 95 %
intervals, and Table 1's summary (min, quartiles, median, mean, max, SD).

Standard errors: a fraction p of n, √(p(1−p)/n); a mean, s/√n; a SD, s/√(2(n−1)) (normal
data). The 95 % intervals are estimate ± 1.96 SE (the fraction's clipped to [0, 1])."""
import math

import numpy as np

Z95 = 1.96


def estimate(value, se, lo=-math.inf, hi=math.inf):
    """{value, se, ci95} as plain floats (a YAML-friendly mapping)."""
    return {"value": float(value), "se": float(se),
            "ci95": [float(max(lo, value - Z95 * se)), float(min(hi, value + Z95 * se))]}


def mean_and_sd(x):
    """(mean estimate, SD estimate) of a sample, each with SE and interval."""
    x = np.asarray(x, dtype=float)
    n = x.size
    if n == 0:
        return estimate(0.0, 0.0), estimate(0.0, 0.0, 0.0)
    sd = float(x.std(ddof=1)) if n > 1 else 0.0
    return (estimate(x.mean(), sd / math.sqrt(n)),
            estimate(sd, sd / math.sqrt(2 * (n - 1)) if n > 1 else 0.0, 0.0))


def fit_ir(readings_m, max_range_m):
    """The error model of one proximity sensor in open space, where every reading should be
    ``max_range_m``: the probability of an error and the mean and SD of its size."""
    r = np.asarray(readings_m, dtype=float)
    errors = max_range_m - r[r < max_range_m - 1e-6]
    n = r.size
    p = errors.size / n if n else 0.0
    mean, sd = mean_and_sd(errors)
    return {"samples": int(n), "errors": int(errors.size),
            "probability": estimate(p, math.sqrt(p * (1 - p) / n) if n else 0.0, 0.0, 1.0),
            "mean_m": mean, "stddev_m": sd}


def fit_axes(values, reference):
    """Per-axis bias (mean − reference) and SD of (N, 3) readings."""
    values = np.asarray(values, dtype=float).reshape(-1, 3)
    bias, sd = [], []
    for axis in range(3):
        m, s = mean_and_sd(values[:, axis])
        m["value"] -= reference[axis]
        m["ci95"] = [c - reference[axis] for c in m["ci95"]]
        bias.append(m)
        sd.append(s)
    return {"samples": int(values.shape[0]), "bias": bias, "stddev": sd}


SUMMARY_COLUMNS = ("min", "1st qu.", "median", "mean", "3rd qu.", "max", "sd")


def summary(x):
    """Table 1's row for a sample: min, quartiles, median, mean, max, SD (NaN when empty)."""
    x = np.asarray(x, dtype=float)
    if x.size == 0:
        return [math.nan] * len(SUMMARY_COLUMNS)
    q1, med, q3 = np.percentile(x, [25, 50, 75])
    return [float(x.min()), float(q1), float(med), float(x.mean()), float(q3),
            float(x.max()), float(x.std(ddof=1)) if x.size > 1 else 0.0]

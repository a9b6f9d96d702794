"""``fit_noise real.bag --scenario rest|straight|wall [-o noise.yaml] [--robot NAME]``

Fits the simulator's noise parameters from a bag of any e-puck (the ``vrep`` or
``epuck_driver`` profile's topics, or V-REP's own) and writes them as a noise file
(``epuck/noise_presets.py``'s format: the simulator loads it with ``~noise_file`` or the launch
argument ``noise_file:=``), with the standard errors, 95 % intervals and sample counts under
``fit``.

What each scenario gives (``scenarios.py``):
- IR, per sensor: in open space every reading below max range is an error; the probability of
  one and the mean and SD of its size (max range − reading). rest and straight: every reading;
  wall: the readings from 1 s after the reversal on (out of range by then); the sensors the
  wall scenario does not use get the pooled fit of the others.
- accelerometer and gyroscope, per axis: bias (mean − the noise-free reading (0, 0, g) and 0)
  and SD; straight: the steady part (0.5 s after the command starts to its end). The SD written
  for x while driving is the sensor's own: the measured total less the wheel slip's part
  v·s/dt in quadrature (``--wheel-slip``, ``--step``: the simulator's, default 0.02 and 0.05 s),
  so the simulation's total matches the bag's. wall: no IMU fit.
Exit status 1 for an unreadable bag or one lacking the scenario's topics (named), 2 for usage.
"""
import argparse
import math
import os
import sys

import numpy as np
import yaml

from epuck_vrep_compat.fidelity.bag_data import BagError, read_scenario_bag
from epuck_vrep_compat.fidelity.scenarios import SCENARIOS
from epuck_vrep_compat.fidelity.stats import fit_axes, fit_ir

GRAVITY_M_S2 = 9.81       # the simulator's g (its e-puck model)


def imu_window(series, scenario, t=None):
    """Mask of the IMU samples (at times ``t``, by default the series' own) that the scenario's
    fit uses: all of them, except while driving straight, where only the steady part counts
    (from 0.5 s after the series' commands start moving to their last moving one; without
    commands, from 1 s on)."""
    t = series.imu_t if t is None else t
    if scenario.name != "straight":
        return np.ones(t.size, bool)
    if series.cmd_t is None:
        return t >= 1.0
    moving = series.cmd_t[np.abs(series.cmd_v) > 1e-9]
    if moving.size == 0:
        return np.ones(t.size, bool)
    return (t >= moving[0] + 0.5) & (t <= moving[-1])


def ir_window(series, scenario, t):
    if scenario.name != "wall":
        return np.ones(t.size, bool)
    end = scenario.drive_s
    if series.cmd_t is not None and np.any(np.abs(series.cmd_v) > 1e-9):
        end = series.cmd_t[np.abs(series.cmd_v) > 1e-9][-1]
    return t >= end + 1.0


def fit(series, scenario, wheel_slip, step_s):
    """(noise file mapping, fit details) for a series."""
    ir_fits = {}
    for k, (t, r, max_range) in sorted(series.ir.items()):
        if k in scenario.ir_sensors:
            ir_fits[k] = fit_ir(r[ir_window(series, scenario, t)], max_range)
    data = {"ir_noise": _ir_params(ir_fits)} if ir_fits else {}
    fit_info = {"scenario": scenario.name, "robot": series.robot,
                "ir": {f"proximity{k}": v for k, v in ir_fits.items()}}
    if scenario.needs_imu:
        mask = imu_window(series, scenario)
        accel = fit_axes(series.accel[mask], (0.0, 0.0, GRAVITY_M_S2))
        gyro = fit_axes(series.gyro[mask], (0.0, 0.0, 0.0))
        sd = [a["value"] for a in accel["stddev"]]
        if scenario.name == "straight" and series.cmd_v is not None:
            speed = float(np.median(np.abs(series.cmd_v[np.abs(series.cmd_v) > 1e-9]))) \
                if np.any(np.abs(series.cmd_v) > 1e-9) else 0.0
            motion = speed * wheel_slip / step_s
            fit_info["accel_x_motion_stddev_m_s2"] = motion
            sd[0] = math.sqrt(max(sd[0] ** 2 - motion ** 2, 0.0))
            data["wheel_slip_stddev"] = wheel_slip     # the slip that correction assumed
        data["imu_noise"] = {
            "accel_bias_m_s2": [a["value"] for a in accel["bias"]],
            "accel_stddev_m_s2": sd,
            "gyro_bias_rad_s": [g["value"] for g in gyro["bias"]],
            "gyro_stddev_rad_s": [g["value"] for g in gyro["stddev"]]}
        fit_info.update(accel=accel, gyro=gyro, accel_sign="vrep" if series.vrep_sign else "ros")
    return data, fit_info


def _ir_params(ir_fits):
    """Per-sensor lists of 8; sensors without a fit take the pooled fit of the others."""
    keys = ("probability", "mean_m", "stddev_m")
    pooled = {key: float(np.mean([f[key]["value"] for f in ir_fits.values()])) for key in keys}
    return {key: [ir_fits[k][key]["value"] if k in ir_fits else pooled[key] for k in range(8)]
            for key in keys}


def parse(argv):
    parser = argparse.ArgumentParser(prog="fit_noise", description=__doc__.split("\n")[2])
    parser.add_argument("bag")
    parser.add_argument("--scenario", required=True, choices=sorted(SCENARIOS))
    parser.add_argument("--robot", default=None,
                        help="robot name as the launch files' names (ePuck0, team_a/epuck_1, / for "
                             "the root namespace; default: the bag's first)")
    parser.add_argument("-o", "--output", default=None,
                        help="noise file to write (default: <bag>_noise.yaml)")
    parser.add_argument("--wheel-slip", type=float, default=0.02)
    parser.add_argument("--step", type=float, default=0.05)
    return parser.parse_args(argv)


def write_noise_file(series, scenario, bag, out, wheel_slip=0.02, step_s=0.05):
    """Fits and writes the noise file ``out``; returns its mapping."""
    data, info = fit(series, scenario, wheel_slip, step_s)
    data["fit"] = dict(info, bag=os.path.abspath(bag))
    with open(out, "w", encoding="utf-8") as f:
        f.write(f"# fit_noise {os.path.basename(bag)} --scenario {scenario.name}: load "
                "with noise_file:=<this file>\n")
        yaml.safe_dump(data, f, sort_keys=False, default_flow_style=None)
    return data


def main(argv=None):
    args = parse(sys.argv[1:] if argv is None else argv)
    scenario = SCENARIOS[args.scenario]
    try:
        series = read_scenario_bag(args.bag, args.robot, scenario)
    except BagError as e:
        print(f"fit_noise: {e}", file=sys.stderr)
        return 1
    out = args.output or os.path.splitext(args.bag)[0] + "_noise.yaml"
    write_noise_file(series, scenario, args.bag, out, args.wheel_slip, args.step)
    print(f"fit_noise: {out} ({len(series.ir)} IR topics, "
          f"{0 if series.imu_t is None else series.imu_t.size} IMU samples)")
    return 0

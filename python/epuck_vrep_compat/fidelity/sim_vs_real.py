"""``sim_vs_real real.bag --scenario rest|straight|wall [-o report_dir] [--robot NAME]
[--rtf 1.0] [--seed 0]``

The paper's section 4.1 comparison for any bag: fits the noise (``fit_noise``), runs the same
scenario in the simulator twice for the bag's duration, with the fitted noise and with none,
replaying the bag's ``cmd_vel`` (or the scenario's drive when it has none), and writes
``report_dir/report.md``: the fitted noise with intervals and counts, Table 1's statistics
(min, quartiles, median, mean, max, SD per axis and per sensor) for real, sim_fitted and
sim_ideal, the IR error rates, and Figs. 3-5 as PNGs beside it (accel.png, proximity.png,
ir_errors.png), with the two simulated bags. Progress goes to stderr. Needs a ROS master (one
is started when none answers). Exit status 1 for an unusable bag, 3 when a run fails.
"""
import argparse
import copy
import os
import sys

import numpy as np
import rospy

from epuck_vrep_compat.compat.epuck_names import VREP
from epuck_vrep_compat.fidelity import report
from epuck_vrep_compat.fidelity.bag_data import (BagError, choose_robot, read_scenario_bag,
                                                 read_series)
from epuck_vrep_compat.fidelity.fit_noise import imu_window, ir_window, write_noise_file
from epuck_vrep_compat.fidelity.scenarios import SCENARIOS
from epuck_vrep_compat.fidelity.sim_run import SimulatorRun, ensure_master, stop_master


def parse(argv):
    parser = argparse.ArgumentParser(prog="sim_vs_real", description=__doc__.split("\n")[3])
    parser.add_argument("bag")
    parser.add_argument("--scenario", required=True, choices=sorted(SCENARIOS))
    parser.add_argument("--robot", default=None)
    parser.add_argument("-o", "--output", default="sim_vs_real")
    parser.add_argument("--rtf", type=float, default=1.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--cmd-vel-scaling", default="si", choices=("si", "vrep", "epuck_driver"),
                        help="units of the bag's cmd_vel: si (m/s, rad/s; default), or the "
                             "V-REP script's or the e-puck driver's (a bag of driver-tuned code)")
    return parser.parse_args(argv)


def commands_of(series, scenario):
    if series.cmd_t is not None and series.cmd_t.size:
        return list(zip(series.cmd_t.tolist(), series.cmd_v.tolist()))
    return scenario.speed_at


def simulate(args, scenario, series, noise_path):
    """{label: Series} of the two simulated runs."""
    world = os.path.join(_share(), "worlds", scenario.world)
    runs = {"sim_fitted": [f"noise_file:={noise_path}"], "sim_ideal": ["noise_preset:=ideal"]}
    commands = commands_of(series, scenario)
    # the bag's commands in their units; the scenario's own drive is in m/s
    scaling = args.cmd_vel_scaling if isinstance(commands, list) else "si"
    out = {}
    for label, launch_args in runs.items():
        bag = os.path.join(args.output, f"{label}.bag")
        SimulatorRun(label, world, launch_args + [f"cmd_vel_scaling:={scaling}"], bag).run(
            series.duration_s, commands, args.seed, args.rtf)
        out[label] = read_series(bag, choose_robot(bag, VREP.robot_name(0)))
    return out


def _share():
    import rospkg
    return rospkg.RosPack().get_path("epuck_vrep_compat")


def fitted_part(sources, scenario):
    """Copies of the series keeping what the noise fit uses: the IR readings in open space
    (wall: after the reversal) and the steady IMU samples (straight: as the paper's Table 1,
    without the start and the stop). The windows come from the real bag's commands, which
    the simulated runs replayed."""
    real = sources["real"]
    kept = {}
    for label, s in sources.items():
        c = copy.copy(s)
        c.ir = {k: tuple(a[ir_window(real, scenario, t)] if isinstance(a, np.ndarray) else a
                         for a in (t, r, m)) for k, (t, r, m) in s.ir.items()}
        if s.imu_t is not None:
            mask = imu_window(real, scenario, s.imu_t)
            c.imu_t, c.accel, c.gyro = s.imu_t[mask], s.accel[mask], s.gyro[mask]
        kept[label] = c
    return kept


def write_report(args, scenario, sources, noise):
    out = args.output
    fitted = fitted_part(sources, scenario)
    figures = [report.plot_accel(sources, os.path.join(out, "accel.png")),
               report.plot_proximity(sources, os.path.join(out, "proximity.png")),
               report.plot_errors(fitted, os.path.join(out, "ir_errors.png"),
                                  scenario.ir_sensors)]
    text = [f"# Simulated vs real: {os.path.basename(args.bag)}, scenario {scenario.name}", "",
            f"Robot {sources['real'].robot}, {sources['real'].duration_s:.2f} s. Sources: real "
            "(the bag), sim_fitted (the simulator with the noise fitted from it: "
            "fitted_noise.yaml), sim_ideal (no noise).", "", "## Fitted noise", "",
            report.fitted_table(noise), "", "## Table 1: statistics", "",
            "The accelerometer over the samples the fit uses (straight: the steady drive, "
            "without start and stop, as Table 1); the proximity sensors over every reading.", "",
            report.table1(fitted, sources), "", "## IR error rate (readings below max range)", "",
            report.error_rates(fitted), "", "## Figures", ""]
    text += [f"![{f}]({f})" for f in figures]
    path = os.path.join(out, "report.md")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(text) + "\n")
    return path


def main(argv=None):
    args = parse(sys.argv[1:] if argv is None else argv)
    scenario = SCENARIOS[args.scenario]
    try:
        real = read_scenario_bag(args.bag, args.robot, scenario)
    except BagError as e:
        print(f"sim_vs_real: {e}", file=sys.stderr)
        return 1
    os.makedirs(args.output, exist_ok=True)
    noise_path = os.path.abspath(os.path.join(args.output, "fitted_noise.yaml"))
    data = write_noise_file(real, scenario, args.bag, noise_path)
    master = ensure_master()
    try:
        rospy.init_node("sim_vs_real", anonymous=True, disable_signals=True)
        sims = simulate(args, scenario, real, noise_path)
    except (RuntimeError, BagError) as e:
        print(f"sim_vs_real: {e}", file=sys.stderr)
        return 3
    finally:
        rospy.signal_shutdown("done")
        stop_master(master)
    path = write_report(args, scenario, dict(real=real, **sims), data)
    print(f"sim_vs_real: report {path}", file=sys.stderr)
    return 0

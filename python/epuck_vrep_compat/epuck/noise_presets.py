"""Named noise presets and the noise file that ``fit_noise`` writes and the simulator loads.

Presets (the option ``noise_preset``):
- ``real_robot`` (default): the paper's real e-puck (``epuck/paper_robot.py``, every number sourced);
- ``vrep``: V-REP's simulated robot of the paper's Table 1: its accelerometer spread (0.0363,
  0.00215, 0.0256 m/s², no bias: its means are 0 and -g), exact proximity sensors ("Sim
  sensor" of Fig. 4), no wheel slip and an exact gyroscope (V-REP's rigid-body dynamics);
- ``ideal``: no noise at all (as with noise switched off).

The noise file (the option ``noise_file``) is YAML with the options' names (the node's
parameters' too), any subset of them:

    ir_noise: {probability: [8], mean_m: [8], stddev_m: [8]}     # or one number each
    imu_noise: {accel_stddev_m_s2: [3], accel_bias_m_s2: [3], gyro_stddev_rad_s: [3],
                gyro_bias_rad_s: [3]}
    wheel_slip_stddev: 0.02
    fit: {...}                      # fit_noise's provenance (bag, counts, intervals): not read

Keys it does not hold keep the preset's value; the node's explicit parameters win over both.
"""
import numpy as np
import yaml

from epuck_vrep_compat.epuck import paper_robot as paper
from epuck_vrep_compat.epuck.noise import (IR_COUNT, IrNoise, NoiseConfigError, NoiseSettings,
                                         per_sensor, triple)

PRESETS = ("real_robot", "vrep", "ideal")
IR_KEYS = ("probability", "mean_m", "stddev_m")
IMU_KEYS = ("accel_stddev_m_s2", "accel_bias_m_s2", "gyro_stddev_rad_s", "gyro_bias_rad_s")
FILE_KEYS = {"ir_noise", "imu_noise", "wheel_slip_stddev", "fit"}


def preset(name: str) -> NoiseSettings:
    """A fresh NoiseSettings of the named preset; NoiseConfigError for an unknown name."""
    if name == "real_robot":
        return NoiseSettings()
    if name == "vrep":
        return NoiseSettings(
            ir=IrNoise(probability=np.zeros(IR_COUNT), mean_m=np.zeros(IR_COUNT),
                       stddev_m=np.zeros(IR_COUNT)),
            accel_stddev_m_s2=np.array(paper.TABLE1_VREP_STDDEV_M_S2),
            accel_bias_m_s2=np.zeros(3), gyro_stddev_rad_s=np.zeros(3),
            gyro_bias_rad_s=np.zeros(3), wheel_slip_stddev=0.0)
    if name == "ideal":
        return NoiseSettings(enabled=False)
    raise NoiseConfigError("noise_preset", f"must be one of {list(PRESETS)}, got {name!r}")


def load_noise_file(path: str, base: NoiseSettings) -> NoiseSettings:
    """``base`` with what the file at ``path`` holds; NoiseConfigError (option ``noise_file``)
    naming the file and the key."""
    try:
        with open(path, encoding="utf-8") as f:
            data = yaml.safe_load(f)
    except (OSError, yaml.YAMLError) as e:
        raise NoiseConfigError("noise_file", f"({path}): cannot read it: {e}") from e
    return apply_mapping(data if data is not None else {}, base, f"({path}): ")


def apply_mapping(data, base: NoiseSettings, where: str) -> NoiseSettings:
    """``base`` updated from a mapping in the noise file's format (validated, keys named); a
    problem is NoiseConfigError of the option ``noise_file``, ``where`` (the file) ahead of it."""
    if not isinstance(data, dict) or not set(data) <= FILE_KEYS:
        raise NoiseConfigError("noise_file", f"{where}noise file must be a mapping with keys "
                                             f"among {sorted(FILE_KEYS)}")
    try:
        return _apply_checked(data, base, where)
    except NoiseConfigError as e:
        if e.option == "noise_file":
            raise
        raise NoiseConfigError("noise_file", f"{where}'{e.option}' {e.problem}") from e


def _apply_checked(data, base: NoiseSettings, where: str) -> NoiseSettings:
    ir = _section(data, "ir_noise", IR_KEYS, where)
    imu = _section(data, "imu_noise", IMU_KEYS, where)
    s = base
    s.ir = IrNoise(
        probability=per_sensor(ir.get("probability", s.ir.probability.tolist()),
                               "ir_noise/probability", 0.0, 1.0),
        mean_m=per_sensor(ir.get("mean_m", s.ir.mean_m.tolist()), "ir_noise/mean_m"),
        stddev_m=per_sensor(ir.get("stddev_m", s.ir.stddev_m.tolist()),
                            "ir_noise/stddev_m", 0.0))
    for key in IMU_KEYS:
        if key in imu:
            setattr(s, key, triple(imu[key], f"imu_noise/{key}",
                                   None if "bias" in key else 0.0))
    if "wheel_slip_stddev" in data:
        slip = data["wheel_slip_stddev"]
        if isinstance(slip, bool) or not isinstance(slip, (int, float)) or not 0.0 <= slip <= 1.0:
            raise NoiseConfigError("noise_file", f"{where}wheel_slip_stddev must be a number "
                                                 f"in [0, 1], got {slip!r}")
        s.wheel_slip_stddev = float(slip)
    return s


def _section(data, key, allowed, where):
    section = data.get(key, {}) or {}
    if not isinstance(section, dict) or not set(section) <= set(allowed):
        raise NoiseConfigError("noise_file", f"{where}'{key}' must be a mapping with keys among "
                                             f"{list(allowed)}")
    return section

"""Noise configuration: validated values, expanded to the per-robot, per-sensor arrays of the core.

The defaults of these classes are the paper's real robot; ``epuck/paper_robot.py`` derives them
(each number with its unit and source); ``epuck/noise_presets.py`` holds the named presets and
the noise file.
"""
from dataclasses import dataclass, field
from typing import Dict, Sequence

import numpy as np

from epuck_vrep_compat.epuck import paper_robot as real

IR_COUNT = 8


class NoiseConfigError(ValueError):
    """A noise option that cannot be used. ``option`` names it as the noise file and the presets
    spell it (``ir_noise/stddev_m``, ``noise_preset``, ``noise_file``), ``problem`` says what is
    wrong with it; the message is ``option '<option>' <problem>``. A layer that takes the option
    from elsewhere (the node's private parameters) words its own message from the two."""

    def __init__(self, option: str, problem: str):
        super().__init__(f"option '{option}' {problem}")
        self.option, self.problem = option, problem


@dataclass
class IrNoise:
    """The e-puck's infrared proximity noise, per sensor: probability, mean and spread."""
    probability: np.ndarray = field(
        default_factory=lambda: np.full(IR_COUNT, real.IR_PROBABILITY))
    mean_m: np.ndarray = field(default_factory=lambda: np.full(IR_COUNT, real.IR_MEAN_M))
    stddev_m: np.ndarray = field(default_factory=lambda: np.full(IR_COUNT, real.IR_STDDEV_M))


@dataclass
class NoiseSettings:
    """All noise sources; ``enabled`` False turns every one of them off."""

    enabled: bool = True
    ir: IrNoise = field(default_factory=IrNoise)
    ir_per_robot: Dict[str, IrNoise] = field(default_factory=dict)     # by robot name
    accel_stddev_m_s2: np.ndarray = field(
        default_factory=lambda: np.array(real.ACCEL_STDDEV_M_S2))
    accel_bias_m_s2: np.ndarray = field(default_factory=lambda: np.array(real.ACCEL_BIAS_M_S2))
    gyro_stddev_rad_s: np.ndarray = field(default_factory=lambda: np.full(3, real.GYRO_STDDEV))
    gyro_bias_rad_s: np.ndarray = field(default_factory=lambda: np.zeros(3))
    wheel_slip_stddev: float = real.WHEEL_SLIP_STDDEV   # relative, per wheel per step

    def apply(self, swarm, robot_names: Sequence[str]):
        """Write the settings into the core swarm's arrays (one row per robot, in order)."""
        n = len(robot_names)
        prob = np.zeros((n, IR_COUNT))
        mean = np.zeros((n, IR_COUNT))
        sd = np.zeros((n, IR_COUNT))
        accel = np.zeros((n, 3))
        gyro = np.zeros((n, 3))
        accel_bias = np.zeros((n, 3))
        gyro_bias = np.zeros((n, 3))
        slip = np.zeros(n)
        if self.enabled:
            for i, name in enumerate(robot_names):
                ir = self.ir_per_robot.get(name, self.ir)
                prob[i], mean[i], sd[i] = ir.probability, ir.mean_m, ir.stddev_m
            accel[:] = self.accel_stddev_m_s2
            gyro[:] = self.gyro_stddev_rad_s
            accel_bias[:] = self.accel_bias_m_s2
            gyro_bias[:] = self.gyro_bias_rad_s
            slip[:] = self.wheel_slip_stddev
        swarm.set_ir_noise(prob, mean, sd)
        swarm.set_imu_noise(accel, gyro)
        swarm.set_imu_bias(accel_bias, gyro_bias)
        swarm.set_slip_noise(slip)


def per_sensor(value, name: str, minimum=None, maximum=None) -> np.ndarray:
    """A scalar or a list of 8 numbers, validated; ``name`` is the option's name."""
    arr = np.asarray(value, dtype=float) if _numeric(value) else None
    if arr is None or arr.shape not in ((), (IR_COUNT,)):
        raise NoiseConfigError(name, f"must be a number or a list of {IR_COUNT} numbers, "
                                     f"got {value!r}")
    arr = np.broadcast_to(arr, (IR_COUNT,)).copy()
    _check_range(arr, name, minimum, maximum)
    return arr


def triple(value, name: str, minimum=0.0) -> np.ndarray:
    """A scalar or a list of 3 numbers (x, y, z), validated; ``name`` is the option's name."""
    arr = np.asarray(value, dtype=float) if _numeric(value) else None
    if arr is None or arr.shape not in ((), (3,)):
        raise NoiseConfigError(name, f"must be a number or a list of 3 numbers, got {value!r}")
    arr = np.broadcast_to(arr, (3,)).copy()
    _check_range(arr, name, minimum, None)
    return arr


def _numeric(value) -> bool:
    values = value if isinstance(value, (list, tuple)) else [value]
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)


def _check_range(arr, name, minimum, maximum):
    if not np.all(np.isfinite(arr)):
        raise NoiseConfigError(name, f"must be finite, got {arr.tolist()}")
    if minimum is not None and np.any(arr < minimum):
        raise NoiseConfigError(name, f"must be >= {minimum}, got {arr.tolist()}")
    if maximum is not None and np.any(arr > maximum):
        raise NoiseConfigError(name, f"must be <= {maximum}, got {arr.tolist()}")

"""Noise configuration: validated values, expanded to the per-robot, per-sensor arrays of the core.

Defaults are in metres and fitted to the real robot where the e-puck paper gives numbers: the IR
noise probability 0.16 (61 noisy readings of 380 on sensor 0) and the accelerometer spread of the
real robot in the paper's Table 1. The IR standard deviation (3 mm) and the gyro spread are ours:
the paper shows the IR histogram but not its figures, and the e-puck 1 has no gyro.
"""
from dataclasses import dataclass, field
from typing import Dict, Sequence

import numpy as np

IR_COUNT = 8


class NoiseConfigError(ValueError):
    """A noise parameter that cannot be used; the message names it."""


@dataclass
class IrNoise:
    """The e-puck's infrared proximity noise, per sensor: probability, mean and spread."""
    probability: np.ndarray = field(default_factory=lambda: np.full(IR_COUNT, 0.16))
    mean_m: np.ndarray = field(default_factory=lambda: np.zeros(IR_COUNT))
    stddev_m: np.ndarray = field(default_factory=lambda: np.full(IR_COUNT, 0.003))


@dataclass
class NoiseSettings:
    """All noise sources; ``enabled`` False turns every one of them off."""

    enabled: bool = True
    ir: IrNoise = field(default_factory=IrNoise)
    ir_per_robot: Dict[str, IrNoise] = field(default_factory=dict)     # by robot name
    accel_stddev_m_s2: np.ndarray = field(
        default_factory=lambda: np.array([0.03559, 0.03079, 0.04930]))
    gyro_stddev_rad_s: np.ndarray = field(default_factory=lambda: np.full(3, 0.005))
    wheel_slip_stddev: float = 0.05       # relative, per wheel per step

    def apply(self, swarm, robot_names: Sequence[str]):
        """Write the settings into the core swarm's arrays (one row per robot, in order)."""
        n = len(robot_names)
        prob = np.zeros((n, IR_COUNT))
        mean = np.zeros((n, IR_COUNT))
        sd = np.zeros((n, IR_COUNT))
        accel = np.zeros((n, 3))
        gyro = np.zeros((n, 3))
        slip = np.zeros(n)
        if self.enabled:
            for i, name in enumerate(robot_names):
                ir = self.ir_per_robot.get(name, self.ir)
                prob[i], mean[i], sd[i] = ir.probability, ir.mean_m, ir.stddev_m
            accel[:] = self.accel_stddev_m_s2
            gyro[:] = self.gyro_stddev_rad_s
            slip[:] = self.wheel_slip_stddev
        swarm.set_ir_noise(prob, mean, sd)
        swarm.set_imu_noise(accel, gyro)
        swarm.set_slip_noise(slip)


def per_sensor(value, name: str, minimum=None, maximum=None) -> np.ndarray:
    """A scalar or a list of 8 numbers, validated; ``name`` is the parameter's name."""
    arr = np.asarray(value, dtype=float) if _numeric(value) else None
    if arr is None or arr.shape not in ((), (IR_COUNT,)):
        raise NoiseConfigError(f"parameter '{name}' must be a number or a list of {IR_COUNT} "
                               f"numbers, got {value!r}")
    arr = np.broadcast_to(arr, (IR_COUNT,)).copy()
    _check_range(arr, name, minimum, maximum)
    return arr


def triple(value, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float) if _numeric(value) else None
    if arr is None or arr.shape not in ((), (3,)):
        raise NoiseConfigError(f"parameter '{name}' must be a number or a list of 3 numbers, "
                               f"got {value!r}")
    arr = np.broadcast_to(arr, (3,)).copy()
    _check_range(arr, name, 0.0, None)
    return arr


def _numeric(value) -> bool:
    values = value if isinstance(value, (list, tuple)) else [value]
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)


def _check_range(arr, name, minimum, maximum):
    if not np.all(np.isfinite(arr)):
        raise NoiseConfigError(f"parameter '{name}' must be finite, got {arr.tolist()}")
    if minimum is not None and np.any(arr < minimum):
        raise NoiseConfigError(f"parameter '{name}' must be >= {minimum}, got {arr.tolist()}")
    if maximum is not None and np.any(arr > maximum):
        raise NoiseConfigError(f"parameter '{name}' must be <= {maximum}, got {arr.tolist()}")

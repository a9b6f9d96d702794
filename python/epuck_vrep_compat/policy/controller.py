"""The shipped controller: a perceptron from the observation to the two wheel speeds, and its
weights file.

``wheels = tanh(W @ observation + b)``: W (2, D), b (2,), each output a wheel speed (left,
right) as a fraction of the motors' 1000 steps/s (the environments' action), so a Braitenberg
vehicle is a perceptron with hand-set weights (:func:`braitenberg`) and CMA-ES evolves W and b
as one flat vector (:meth:`Perceptron.from_flat`).

The weights file is JSON (readable, diffable, a few hundred bytes)::

    {"format": "epuck_vrep_compat/perceptron-1",
     "observation": {"imu": false, "neighbours": 0, "neighbour_range_m": 0.5,
                     "camera": false, "camera_bins": 16, "names": ["ir0", ..., "ir7"]},
     "weights": [[...D...], [...D...]], "bias": [bl, br],
     "meta": {...}}                          # free: provenance (task, seed, fitness)

The observation's layout is recorded with the weights, so ``policy_node`` builds the vector
the weights were made for (a file without the camera keys, written before the camera row
existed, has no camera block).
"""
import json
import math
from typing import Optional

import numpy as np

from epuck_vrep_compat.geometry.fixed_order import libm, weighted_sums
from epuck_vrep_compat.policy.observation import IR_COUNT, ObservationLayout

FORMAT = "epuck_vrep_compat/perceptron-1"
# Braitenberg's avoider on the e-puck's sensors (0, 1, 2 on the right front and side, 5, 6, 7
# on the left, 3 and 4 at the back): what the right sees slows the left wheel, and so on.
# An obstacle straight ahead (0 and 7 alike) backs the robot away turning left.
_AVOID_LEFT = (-1.0, -0.8, -0.5, 0.1, 0.1, 0.5, 0.6, 0.3)
_AVOID_RIGHT = (0.6, 0.6, 0.5, 0.1, 0.1, -0.5, -0.8, -1.0)
_CRUISE = 0.5


class Perceptron:
    """wheels = tanh(W @ obs + b): obs (..., D) -> (..., 2) in [-1, 1]; the same bits for one
    observation alone and in a batch, on any processor (W @ obs added in a fixed order, tanh
    the C library's: :mod:`epuck_vrep_compat.geometry.fixed_order`)."""

    def __init__(self, weights, bias, layout: ObservationLayout, meta: Optional[dict] = None):
        self.weights = np.asarray(weights, dtype=float).reshape(2, -1)
        self.bias = np.asarray(bias, dtype=float).reshape(2)
        self.layout = layout
        self.meta = dict(meta or {})
        if self.weights.shape[1] != layout.size:
            raise ValueError(f"weights have {self.weights.shape[1]} inputs, the observation "
                             f"layout {layout.size}")

    @staticmethod
    def parameter_count(layout: ObservationLayout) -> int:
        return 2 * layout.size + 2

    @classmethod
    def from_flat(cls, flat, layout: ObservationLayout, meta=None) -> "Perceptron":
        """From one vector of :meth:`parameter_count` values: W row by row, then b."""
        flat = np.asarray(flat, dtype=float)
        if flat.shape != (cls.parameter_count(layout),):
            raise ValueError(f"need {cls.parameter_count(layout)} parameters, got {flat.shape}")
        return cls(flat[:-2].reshape(2, layout.size), flat[-2:], layout, meta)

    def flat(self) -> np.ndarray:
        return np.concatenate([self.weights.ravel(), self.bias])

    def __call__(self, observation) -> np.ndarray:
        return libm(math.tanh, weighted_sums(observation, self.weights) + self.bias)

    def save(self, path: str):
        data = {"format": FORMAT, "observation": self.layout.to_dict(),
                "weights": self.weights.tolist(), "bias": self.bias.tolist(), "meta": self.meta}
        with open(path, "w", encoding="utf-8") as f:
            json.dump(data, f, indent=1)
            f.write("\n")

    @classmethod
    def load(cls, path: str) -> "Perceptron":
        """The controller of a weights file; ValueError naming the file on a wrong one."""
        try:
            with open(path, encoding="utf-8") as f:
                data = json.load(f)
            if not isinstance(data, dict) or data.get("format") != FORMAT:
                raise ValueError(f"format must be '{FORMAT}'")
            return cls(data["weights"], data["bias"],
                       ObservationLayout.from_dict(data["observation"]), data.get("meta"))
        except (OSError, KeyError, TypeError, ValueError) as e:
            raise ValueError(f"weights file {path}: {e}") from e


def braitenberg(layout: ObservationLayout = ObservationLayout()) -> Perceptron:
    """A hand-set obstacle avoider (Braitenberg's vehicle 3b) on any layout: IR weights only,
    cruising at about half speed."""
    weights = np.zeros((2, layout.size))
    weights[0, :IR_COUNT] = _AVOID_LEFT
    weights[1, :IR_COUNT] = _AVOID_RIGHT
    weights[:, :IR_COUNT] *= 2.0
    cruise = np.arctanh(_CRUISE)
    return Perceptron(weights, (cruise, cruise), layout, {"origin": "braitenberg"})

"""Coloured regions of the floor (scene file section ``floor_regions``), which the e-pucks'
ground sensors see: a line to follow, a black spot, a grey band.

Each region is an axis-aligned rectangle in the world frame (``min_m``, ``max_m``: corners,
metres) with an RGB ``color`` in 0..1; where regions overlap, the later one in the list lies on
top. Outside every region the floor has the arena's ``floor_color``::

    floor_regions:
      - {min_m: [-0.5, -0.01], max_m: [0.5, 0.01], color: [0, 0, 0]}   # a black line along x
"""
from dataclasses import dataclass
from typing import List, Sequence, Tuple

import numpy as np

from epuck_vrep_compat.scene.validation import SceneError, as_list, color, numbers, only


@dataclass(frozen=True)
class FloorRegion:
    """One coloured rectangle of the floor."""

    min_m: Tuple[float, float]
    max_m: Tuple[float, float]
    color: Tuple[float, float, float]


def parse_floor_regions(v, where: str) -> List[FloorRegion]:
    regions = []
    for i, d in enumerate(as_list(v, where)):
        here = f"{where}[{i}]"
        if not isinstance(d, dict):
            raise SceneError(f"{here} must be a mapping")
        only(d, {"min_m", "max_m", "color"}, here)
        for key in ("min_m", "max_m", "color"):
            if key not in d:
                raise SceneError(f"{here}: missing '{key}'")
        lo = numbers(d["min_m"], 2, f"{here}.min_m")
        hi = numbers(d["max_m"], 2, f"{here}.max_m")
        if not (lo[0] < hi[0] and lo[1] < hi[1]):
            raise SceneError(f"{here}: min_m must be below max_m in x and y, got {lo}, {hi}")
        regions.append(FloorRegion(tuple(lo), tuple(hi), color(d["color"], f"{here}.color")))
    return regions


def floor_rgb(regions: Sequence[FloorRegion], base_rgb, xy) -> np.ndarray:
    """RGB (M, 3) of the floor at the points ``xy`` (M, 2): the last region holding each point,
    else ``base_rgb``."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    out = np.tile(np.asarray(base_rgb, dtype=float), (xy.shape[0], 1))
    for region in regions:
        inside = ((xy[:, 0] >= region.min_m[0]) & (xy[:, 0] <= region.max_m[0])
                  & (xy[:, 1] >= region.min_m[1]) & (xy[:, 1] <= region.max_m[1]))
        out[inside] = region.color
    return out

"""A seeded random walk of the operator in the cell, generated once when the cell is built.

From the walk's own seed (its own numpy Generator: nothing else draws from it, so the same seed
gives the same walk under any simulation seed and any monitor): a start anywhere on the floor,
then ``legs`` legs. Each leg's goal is, with ``approach_probability``, near a robot's base (at a
distance drawn from ``approach_distance_m``, in a direction drawn at random; the robots in
turn, in an order shuffled each round, so every robot is approached), else anywhere on the
floor; goals near a wall are pulled back inside. He walks straight to the goal at a speed drawn
from ``speed_m_s``, facing it, then stands for a pause drawn from ``pause_s``, turning towards
the next goal as he stands. After the last leg he stays where he is.

"On the floor" means the arena's floor kept a body radius from its walls; obstacles and robots
are no obstacles to him (he is kinematic, as V-REP's walking "Bill" is).
"""
import math
from dataclasses import dataclass
from typing import List, Sequence, Tuple

import numpy as np

from epuck_vrep_compat.cell.devices.operator_motion import TimedPath


@dataclass
class WalkLeg:
    """One leg as generated: its goal, speed and pause, and the robot it approaches (or None)."""
    goal: Tuple[float, float]
    speed_m_s: float
    pause_s: float
    approaches: str = None


class Floor:
    """The rectangle the operator's axis may be in: [x_min, x_max] x [y_min, y_max]."""

    def __init__(self, x_min, x_max, y_min, y_max):
        if not (x_min < x_max and y_min < y_max):
            raise ValueError(f"the operator has no floor to walk on: [{x_min}, {x_max}] x "
                             f"[{y_min}, {y_max}] m (is the arena smaller than his body?)")
        self.x_min, self.x_max, self.y_min, self.y_max = x_min, x_max, y_min, y_max

    @classmethod
    def of_arena(cls, size_m, margin_m: float):
        """The arena's floor (centred on the origin) less ``margin_m`` from every wall."""
        hx, hy = 0.5 * size_m[0] - margin_m, 0.5 * size_m[1] - margin_m
        return cls(-hx, hx, -hy, hy)

    def contains(self, x, y) -> bool:
        """True when every (x, y) given lies on the floor (arrays too)."""
        x, y = np.asarray(x), np.asarray(y)
        return bool(((x >= self.x_min) & (x <= self.x_max)
                     & (y >= self.y_min) & (y <= self.y_max)).all())

    def clip(self, x, y):
        return (min(max(x, self.x_min), self.x_max), min(max(y, self.y_min), self.y_max))

    def draw(self, rng):
        return (float(rng.uniform(self.x_min, self.x_max)),
                float(rng.uniform(self.y_min, self.y_max)))

    def __str__(self):
        return f"[{self.x_min:g}, {self.x_max:g}] x [{self.y_min:g}, {self.y_max:g}] m"


def plan_walk(walk, floor: Floor, robots: Sequence[Tuple[str, float, float]]):
    """(start (x, y), [WalkLeg]) of ``walk`` (a WalkSpec) on ``floor``; ``robots``: each
    robot's (name, base x, base y)."""
    rng = np.random.default_rng(walk.seed)
    start = floor.draw(rng)
    legs: List[WalkLeg] = []
    turn: List[int] = []                   # the robots still to approach in this round
    for _ in range(walk.legs):
        approaches = None
        if robots and rng.random() < walk.approach_probability:
            if not turn:
                turn = [int(k) for k in rng.permutation(len(robots))]
            approaches, bx, by = robots[turn.pop(0)]
            r = rng.uniform(*walk.approach_distance_m)
            a = rng.uniform(-math.pi, math.pi)
            goal = floor.clip(bx + r * math.cos(a), by + r * math.sin(a))
        else:
            goal = floor.draw(rng)
        legs.append(WalkLeg(goal, float(rng.uniform(*walk.speed_m_s)),
                            float(rng.uniform(*walk.pause_s)), approaches))
    return start, legs


def walk_path(start, legs: Sequence[WalkLeg]) -> TimedPath:
    """The keyframes of a planned walk: per leg its departure and its arrival; the heading
    changes while he stands (at once when the pause is 0)."""
    t, (x, y) = 0.0, start
    heading = None
    keys = []
    for leg in legs:
        gx, gy = leg.goal
        length = math.hypot(gx - x, gy - y)
        new_heading = math.atan2(gy - y, gx - x) if length > 0.0 else heading
        if heading is None:
            heading = new_heading if new_heading is not None else 0.0
            new_heading = heading
        keys.append((t, x, y, new_heading))                 # departs facing the goal
        t += length / leg.speed_m_s
        keys.append((t, gx, gy, new_heading))                # arrives
        t += leg.pause_s                                     # stands, turning to the next
        x, y, heading = gx, gy, new_heading
    keys.append((t, x, y, heading))
    return TimedPath(*np.array(keys, dtype=float).T)


def generate_walk(walk, floor: Floor, robots) -> Tuple[TimedPath, List[WalkLeg]]:
    """The walk as a timed path, and its legs (for tests and logs)."""
    start, legs = plan_walk(walk, floor, robots)
    return walk_path(start, legs), legs

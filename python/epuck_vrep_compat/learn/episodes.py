"""Episodes of B worlds for the vector environments (``vector.py``: one agent a world;
``parallel_vector.py``: every agent of a world): per-world seeds and Gymnasium's ``NEXT_STEP``
autoreset, written once.

``reset(seed=s)`` seeds world b with ``s + b`` (so world b is the one-world environment reset
with ``s + b``), ``options={"world_seeds": [...]}`` each world with its own, neither lets each
world's generator go on. A world whose episode ended at a step is reset alone at the next step:
its actions are ignored, its robots rest, its rewards are 0, and that step returns its first
observation.
"""
import numpy as np

from epuck_vrep_compat.learn.worlds import Worlds


def world_seeds(count: int, seed=None, options=None):
    """The seed of each of ``count`` worlds for a reset (None: the world's generator goes on);
    ``options["world_seeds"]`` wins over ``seed``."""
    given = (options or {}).get("world_seeds")
    if given is not None:
        if len(given) != count:
            raise ValueError(f"options['world_seeds'] needs {count} seeds, got {len(given)}")
        return [int(s) for s in given]
    if seed is None:
        return [None] * count
    return [int(seed) + b for b in range(count)]


class Episodes:
    """The episodes of every world of ``worlds`` (a :class:`Worlds`), for its agents."""

    def __init__(self, worlds: Worlds):
        self.worlds = worlds
        self.ended = np.zeros(worlds.count, dtype=bool)

    def reset(self, seed=None, options=None):
        """Every world anew (seeds as the module says), then the step at rest that gives the
        first observations."""
        worlds = self.worlds
        for b, s in enumerate(world_seeds(worlds.count, seed, options)):
            if s is not None:
                worlds.seed(b, s)
            worlds.place(b)
        worlds.step(np.zeros((worlds.count, len(worlds.agents), 2)),
                    rest=np.ones(worlds.count, dtype=bool))
        self.ended[:] = False

    def step(self, actions):
        """One step of every world, ``actions`` (B, A, 2). Returns the agents' rewards (B, A),
        ``terminated`` and ``truncated`` (B,) of each world's episode."""
        worlds = self.worlds
        restart = self.ended.copy()
        for b in np.flatnonzero(restart):
            worlds.place(b)
        rewards = worlds.step(np.asarray(actions, dtype=float).reshape(
            worlds.count, len(worlds.agents), 2), rest=restart)[:, worlds.agents]
        rewards[restart] = 0.0
        truncated = (worlds.elapsed >= worlds.episode_steps) & ~restart
        terminated = np.zeros(worlds.count, dtype=bool)
        self.ended = truncated | terminated
        return rewards, terminated, truncated

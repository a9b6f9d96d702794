"""The vector environment: ``num_envs`` worlds of one task in one ``BatchedWorlds``, each with
one learning robot, stepped in one core call (``gymnasium.make_vec(id, num_envs=B)``).

Spaces, rewards and ``info`` keys are the single-robot environment's, batched (``info``: arrays
of B rows). Autoreset: Gymnasium's default ``NEXT_STEP``: the step after a world's episode
ended resets that world (its action is ignored, its reward 0) and returns its first
observation. ``reset(seed=s)`` seeds world b with ``s + b``, ``reset(options={"world_seeds":
[s0, s1, ...]})`` each world with its own (the same arena for several worlds: CMA-ES scores its
candidates on common arenas); ``render()`` gives one RGB array per world.
"""
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from epuck_vrep_compat.learn.env import METADATA, spaces
from epuck_vrep_compat.learn.tasks import make_task
from epuck_vrep_compat.learn.worlds import Worlds
from epuck_vrep_compat.policy.observation import CAMERA_BINS


class EpuckVectorEnv(VectorEnv):
    """``num_envs`` worlds of ``task`` (the arguments are :class:`EpuckEnv`'s)."""

    metadata = dict(METADATA, autoreset_mode=AutoresetMode.NEXT_STEP)

    def __init__(self, num_envs: int = 1, task: str = "obstacle_avoidance", render_mode=None,
                 noise: str = "real_robot", robots=None, imu: bool = False,
                 episode_steps: int = 400, camera: bool = False,
                 camera_bins: int = CAMERA_BINS, camera_spec=None):
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.num_envs, self.render_mode = num_envs, render_mode
        self.worlds = Worlds(make_task(task, robots, imu, camera, camera_bins), num_envs, noise,
                             episode_steps=episode_steps, camera=camera_spec)
        self.single_observation_space, self.single_action_space = spaces(self.worlds.layout)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._ended = np.zeros(num_envs, dtype=bool)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        world_seeds = (options or {}).get("world_seeds")
        if world_seeds is not None and len(world_seeds) != self.num_envs:
            raise ValueError(f"options['world_seeds'] needs {self.num_envs} seeds, got "
                             f"{len(world_seeds)}")
        for b in range(self.num_envs):
            if world_seeds is not None:
                self.worlds.seed(b, int(world_seeds[b]))
            elif seed is not None:
                self.worlds.seed(b, seed + b)
            self.worlds.place(b)
        self.worlds.step(np.zeros((self.num_envs, len(self.worlds.agents), 2)),
                         rest=np.ones(self.num_envs, dtype=bool))
        self._ended[:] = False
        return self.worlds.agent_obs()[:, 0], self._infos()

    def step(self, actions):
        restart = self._ended.copy()
        for b in np.flatnonzero(restart):
            self.worlds.place(b)
        rewards = self.worlds.step(np.asarray(actions, dtype=float).reshape(
            self.num_envs, len(self.worlds.agents), 2), rest=restart)
        reward = rewards[:, self.worlds.agents[0]].copy()
        reward[restart] = 0.0
        truncated = (self.worlds.elapsed >= self.worlds.episode_steps) & ~restart
        terminated = np.zeros(self.num_envs, dtype=bool)
        self._ended = truncated | terminated
        return self.worlds.agent_obs()[:, 0], reward, terminated, truncated, self._infos()

    def _infos(self):
        infos = [self.worlds.info(b) for b in range(self.num_envs)]
        return {key: np.stack([i[key] for i in infos]) for key in infos[0]}

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        return tuple(self.worlds.draw(b) for b in range(self.num_envs))

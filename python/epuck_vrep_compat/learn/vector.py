"""The vector environment: ``num_envs`` worlds of one task in one ``BatchedWorlds``, each with
one learning robot, stepped in one core call (``gymnasium.make_vec(id, num_envs=B)``).

Spaces, rewards and ``info`` keys are the single-robot environment's, batched (``info``: arrays
of B rows). Autoreset: Gymnasium's default ``NEXT_STEP``: the step after a world's episode
ended resets that world (its action is ignored, its reward 0) and returns its first
observation. ``reset(seed=s)`` seeds world b with ``s + b``, ``reset(options={"world_seeds":
[s0, s1, ...]})`` each world with its own (the same arena for several worlds: CMA-ES scores its
candidates on common arenas); ``render()`` gives one RGB array per world. Both are
:mod:`epuck_vrep_compat.learn.episodes`', shared with the swarm's vector environment.
"""
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from epuck_vrep_compat.learn.env import METADATA, check_render_mode, spaces
from epuck_vrep_compat.learn.episodes import Episodes
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
        self.num_envs, self.render_mode = num_envs, check_render_mode(render_mode)
        self.worlds = Worlds(make_task(task, robots, imu, camera, camera_bins), num_envs, noise,
                             episode_steps=episode_steps, camera=camera_spec)
        self.single_observation_space, self.single_action_space = spaces(self.worlds.layout)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.episodes = Episodes(self.worlds)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.episodes.reset(seed, options)
        return self.worlds.agent_obs()[:, 0], self._infos()

    def step(self, actions):
        actions = np.asarray(actions, dtype=float)
        if actions.shape != (self.num_envs, 2):      # a flat or transposed batch would reshape
            raise ValueError(f"actions must be ({self.num_envs}, 2), got {actions.shape}")
        rewards, terminated, truncated = self.episodes.step(actions)
        return self.worlds.agent_obs()[:, 0], rewards[:, 0], terminated, truncated, self._infos()

    def _infos(self):
        infos = self.worlds.agent_infos()
        return {"in_contact": infos["in_contact"][:, 0], "pose": infos["pose"][:, 0],
                "elapsed_steps": infos["elapsed_steps"]}

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        return tuple(self.worlds.draw(b) for b in range(self.num_envs))

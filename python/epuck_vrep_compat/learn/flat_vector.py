"""The swarm's B worlds x A agents as one Gymnasium ``VectorEnv`` of B x A sub-environments,
each one agent: what SuperSuit's ``concat_vec_envs_v1(pettingzoo_env_to_vec_env_v1(env), B)``
makes of a PettingZoo ``ParallelEnv``, for single-agent learners with parameters shared by
every agent (Stable-Baselines3, CleanRL), here without SuperSuit and in one core call a step.

Row ``b * A + a`` is agent ``a`` (``possible_agents[a]``) of world ``b``, SuperSuit's order.
Spaces: ``single_observation_space`` and ``single_action_space`` one agent's, the batched
spaces over B x A. Rewards, terminations and truncations per row; ``info``: ``in_contact``
(B x A,), ``pose`` (B x A, 3), ``elapsed_steps`` (B x A,: the row's world's). Autoreset is
Gymnasium's ``NEXT_STEP`` per world (every agent of a world at once; SuperSuit resets in the
same step and puts the last observation in ``info``), ``reset(seed=s)`` seeds world b with
``s + b`` as ``concat_vec_envs_v1`` does, ``options={"world_seeds": [...]}`` each world;
``render()`` gives one RGB array per world (B, not B x A).
"""
import numpy as np
from gymnasium.vector import VectorEnv
from gymnasium.vector.utils import batch_space

from epuck_vrep_compat.learn.parallel_vector import EpuckParallelVectorEnv


class EpuckFlatVectorEnv(VectorEnv):
    """The B x A agents of ``env`` (an :class:`EpuckParallelVectorEnv`) as one vector
    environment, ``num_envs`` = B x A."""

    def __init__(self, env: EpuckParallelVectorEnv):
        self.env = env
        self.metadata = env.metadata
        self.render_mode = env.render_mode
        self.worlds, self.agents_per_world = env.num_envs, env.num_agents
        self.num_envs = self.worlds * self.agents_per_world
        agent = env.possible_agents[0]
        self.single_observation_space = env.single_observation_space(agent)
        self.single_action_space = env.single_action_space(agent)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        obs, infos = self.env.reset_arrays(seed, options)
        return self._rows(obs), self._infos(infos)

    def step(self, actions):
        actions = np.asarray(actions, dtype=float)
        if actions.shape != (self.num_envs, 2):
            raise ValueError(f"actions must be ({self.num_envs}, 2), got {actions.shape}")
        obs, rewards, terminated, truncated, infos = self.env.step_arrays(
            actions.reshape(self.worlds, self.agents_per_world, 2))
        return (self._rows(obs), self._rows(rewards), self._rows(terminated),
                self._rows(truncated), self._infos(infos))

    def _rows(self, values):
        """(B, A, ...) as (B x A, ...), row b * A + a."""
        return values.reshape((self.num_envs,) + values.shape[2:])

    def _infos(self, infos):
        return {"in_contact": self._rows(infos["in_contact"]), "pose": self._rows(infos["pose"]),
                "elapsed_steps": np.repeat(infos["elapsed_steps"], self.agents_per_world)}

    def render(self):
        return self.env.render()

    def close_extras(self, **kwargs):
        self.env.close()

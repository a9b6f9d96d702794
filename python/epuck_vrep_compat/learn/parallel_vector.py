"""The swarm batched: ``num_envs`` worlds (B) of :class:`~epuck_vrep_compat.learn.parallel.
EpuckParallelEnv`, each with the same A agents (``epuck_0``, ``epuck_1``, ...), every robot of
every world stepped in one core call.

The API is PettingZoo's ``ParallelEnv`` with every value batched over the worlds, as vectorised
PettingZoo environments give it (AgileRL's ``PettingZooVecEnv``): ``reset`` and ``step`` take
and return dicts keyed by agent whose values have a leading axis of B (observations (B, D),
rewards, terminations and truncations (B,), each agent's ``info`` a dict of arrays of B rows);
``step`` also takes the actions as one array (B, A, 2), agents in ``possible_agents`` order.
``reset_arrays`` and ``step_arrays`` give the same as arrays (B, A, ...). Spaces:
``single_observation_space(agent)`` and ``single_action_space(agent)`` are one agent's in one
world (the one-world environment's), ``observation_space(agent)`` and ``action_space(agent)``
batched over B.

A world is the one-world environment: the same observations, rewards, truncations and ``info``
for the same seed and actions. Autoreset, per world, is the Gymnasium vector environment's
(``NEXT_STEP``, :mod:`epuck_vrep_compat.learn.episodes`): the step after a world's episode ended
resets that world alone, ignores its actions, gives its agents reward 0 and its first
observation, so ``agents`` is always every agent. ``reset(seed=s)`` seeds world b with
``s + b``, ``options={"world_seeds": [...]}`` each world. The Gymnasium vector environment of
the B x A agents (SuperSuit's ``concat_vec_envs_v1(pettingzoo_env_to_vec_env_v1(env), B)``) is
:class:`~epuck_vrep_compat.learn.flat_vector.EpuckFlatVectorEnv` on this one.
"""
import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from epuck_vrep_compat.learn.env import METADATA, check_render_mode, spaces
from epuck_vrep_compat.learn.episodes import Episodes
from epuck_vrep_compat.learn.parallel import swarm_worlds
from epuck_vrep_compat.policy.observation import CAMERA_BINS


class EpuckParallelVectorEnv:
    """``num_envs`` worlds of ``task`` (the other arguments are :class:`EpuckParallelEnv`'s)."""

    metadata = dict(METADATA, name="epuck_swarm_vector_v0",
                    autoreset_mode=AutoresetMode.NEXT_STEP)

    def __init__(self, num_envs: int = 1, task: str = "aggregation", robots=None,
                 render_mode=None, noise: str = "real_robot", imu: bool = False,
                 episode_steps: int = 400, camera: bool = False,
                 camera_bins: int = CAMERA_BINS, camera_spec=None):
        self.num_envs, self.render_mode = num_envs, check_render_mode(render_mode)
        self.worlds = swarm_worlds(task, robots, num_envs, noise, imu, episode_steps, camera,
                                   camera_bins, camera_spec)
        self.possible_agents = [f"epuck_{r}" for r in self.worlds.agents]
        self.agents = list(self.possible_agents)
        self.num_agents = self.max_num_agents = len(self.possible_agents)
        self._single = spaces(self.worlds.layout)
        self._batched = tuple(batch_space(s, num_envs) for s in self._single)
        self.episodes = Episodes(self.worlds)

    def single_observation_space(self, agent):
        """One agent's observation space in one world."""
        return self._single[0]

    def single_action_space(self, agent):
        """One agent's action space in one world: Box(-1, 1, (2,))."""
        return self._single[1]

    def observation_space(self, agent):
        """One agent's observation space over the B worlds (B, D)."""
        return self._batched[0]

    def action_space(self, agent):
        """One agent's action space over the B worlds (B, 2)."""
        return self._batched[1]

    def reset_arrays(self, seed=None, options=None):
        """:meth:`reset` as arrays: observations (B, A, D), ``info`` (``in_contact`` (B, A),
        ``pose`` (B, A, 3), ``elapsed_steps`` (B,))."""
        self.episodes.reset(seed, options)
        return self.worlds.agent_obs(), self.worlds.agent_infos()

    def step_arrays(self, actions):
        """:meth:`step` as arrays: ``actions`` (B, A, 2); observations (B, A, D), rewards,
        terminations and truncations (B, A), ``info`` as :meth:`reset_arrays`'."""
        actions = np.asarray(actions, dtype=float)
        if actions.shape != (self.num_envs, self.num_agents, 2):
            raise ValueError(f"actions must be ({self.num_envs}, {self.num_agents}, 2), got "
                             f"{actions.shape}")
        rewards, terminated, truncated = self.episodes.step(actions)
        every_agent = np.ones(self.num_agents, dtype=bool)
        return (self.worlds.agent_obs(), rewards, np.outer(terminated, every_agent),
                np.outer(truncated, every_agent), self.worlds.agent_infos())

    def reset(self, seed=None, options=None):
        """Every world anew: ({agent: observations (B, D)}, {agent: {key: (B, ...)}})."""
        obs, infos = self.reset_arrays(seed, options)
        return self._by_agent(obs), self._infos_by_agent(infos)

    def step(self, actions):
        """``actions``: {agent: (B, 2)} (an agent left out rests) or an array (B, A, 2).
        Returns observations, rewards, terminations, truncations and infos keyed by agent."""
        if isinstance(actions, dict):
            unknown = set(actions) - set(self.possible_agents)
            if unknown:
                raise KeyError(f"no such agents: {sorted(unknown)}")
            stacked = np.zeros((self.num_envs, self.num_agents, 2))
            for k, agent in enumerate(self.possible_agents):
                if agent in actions:
                    stacked[:, k] = np.reshape(actions[agent], (self.num_envs, 2))
            actions = stacked
        obs, rewards, terminated, truncated, infos = self.step_arrays(actions)
        return (self._by_agent(obs), self._by_agent(rewards), self._by_agent(terminated),
                self._by_agent(truncated), self._infos_by_agent(infos))

    def _by_agent(self, values):
        """{agent: its column of ``values`` (B, A, ...)}, each an array of its own."""
        return {agent: np.ascontiguousarray(values[:, k])
                for k, agent in enumerate(self.possible_agents)}

    def _infos_by_agent(self, infos):
        contact, pose = self._by_agent(infos["in_contact"]), self._by_agent(infos["pose"])
        return {agent: {"in_contact": contact[agent], "pose": pose[agent],
                        "elapsed_steps": infos["elapsed_steps"].copy()}
                for agent in self.possible_agents}

    def render(self):
        """One RGB array (256, 256, 3) per world, or None without ``render_mode="rgb_array"``."""
        if self.render_mode != "rgb_array":
            return None
        return tuple(self.worlds.draw(b) for b in range(self.num_envs))

    def close(self):
        pass

    @property
    def unwrapped(self):
        return self

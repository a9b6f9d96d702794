"""The swarm as a PettingZoo ``ParallelEnv``: one world of a task in the core's
``BatchedWorlds``, every robot but a leader an agent (``epuck_0``, ``epuck_1``, ...: the
robot's index), all stepped in one core call. Per agent the single-robot environment's spaces,
reward and ``info``; an episode ends for every agent at once after ``episode_steps``
(truncation), after which ``agents`` is empty until ``reset``.
"""
import functools

import numpy as np
from pettingzoo import ParallelEnv

from epuck_vrep_compat.learn.env import METADATA, check_render_mode, spaces
from epuck_vrep_compat.learn.tasks import make_task
from epuck_vrep_compat.learn.worlds import Worlds
from epuck_vrep_compat.policy.observation import CAMERA_BINS


def swarm_worlds(task: str, robots, worlds: int, noise: str, imu: bool, episode_steps: int,
                 camera: bool, camera_bins: int, camera_spec) -> Worlds:
    """``worlds`` worlds of ``task`` whose agents are every robot but a leader (``robots``:
    None is 4 for obstacle avoidance, else the task's number)."""
    if robots is None and task == "obstacle_avoidance":
        robots = 4
    return Worlds(make_task(task, robots, imu, camera, camera_bins), worlds, noise,
                  episode_steps=episode_steps, camera=camera_spec, multi_agent=True)


class EpuckParallelEnv(ParallelEnv):
    """``robots`` e-pucks of ``task`` (default: 4 for obstacle avoidance, else the task's)."""

    metadata = dict(METADATA, name="epuck_swarm_v0", is_parallelizable=True)

    def __init__(self, task: str = "aggregation", robots=None, render_mode=None,
                 noise: str = "real_robot", imu: bool = False, episode_steps: int = 400,
                 camera: bool = False, camera_bins: int = CAMERA_BINS, camera_spec=None):
        self.render_mode = check_render_mode(render_mode)
        self.worlds = swarm_worlds(task, robots, 1, noise, imu, episode_steps, camera,
                                   camera_bins, camera_spec)
        self.possible_agents = [f"epuck_{r}" for r in self.worlds.agents]
        self.agents = []
        self._spaces = spaces(self.worlds.layout)

    @functools.lru_cache(maxsize=None)
    def observation_space(self, agent):
        return self._spaces[0]

    @functools.lru_cache(maxsize=None)
    def action_space(self, agent):
        return self._spaces[1]

    def reset(self, seed=None, options=None):
        if seed is not None:
            self.worlds.seed(0, seed)
        self.worlds.place(0)
        self.worlds.step(np.zeros((1, len(self.possible_agents), 2)), rest=[True])
        self.agents = list(self.possible_agents)
        return self._observations(), self._infos()

    def step(self, actions):
        acting = np.zeros((1, len(self.possible_agents), 2))
        for k, agent in enumerate(self.possible_agents):
            if agent in actions:
                acting[0, k] = actions[agent]
        rewards = self.worlds.step(acting)[0]
        done = bool(self.worlds.elapsed[0] >= self.worlds.episode_steps)
        out = (self._observations(),
               {a: float(rewards[r]) for a, r in zip(self.possible_agents, self.worlds.agents)},
               {a: False for a in self.agents}, {a: done for a in self.agents}, self._infos())
        if done:
            self.agents = []
        return out

    def _observations(self):
        obs = self.worlds.agent_obs()[0]
        return {a: obs[k] for k, a in enumerate(self.possible_agents) if a in self.agents}

    def _infos(self):
        return {a: self.worlds.info(0, k) for k, a in enumerate(self.possible_agents)
                if a in self.agents}

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        return self.worlds.draw(0)

    def close(self):
        pass

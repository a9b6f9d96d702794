"""The single-robot Gymnasium environment: one world of a task, one learning robot.

Observation: the policy package's vector (:mod:`epuck_vrep_compat.policy.observation`) of the
task's layout, float32: 8 IR activations in [0, 1], with ``imu=True`` the IMU block, the
neighbours' block of the aggregation and follow tasks, and with ``camera=True`` the camera row
(``camera_bins`` gray levels in [0, 1] of the robot's camera image, rendered each step).
Action: Box(-1, 1, (2,)), the left and right wheel speeds as fractions of the motors' 1000
steps/s (6.28 rad/s). One step is 50 ms of simulated time; an episode is truncated after
``episode_steps`` (400: 20 s) and never terminates. Reward: the task's
(:mod:`epuck_vrep_compat.learn.tasks`). ``info``: the agent's ``in_contact``, ``pose`` (ground
truth x, y, yaw) and ``elapsed_steps``.
"""
import gymnasium as gym
import numpy as np

from epuck_vrep_compat.learn.tasks import make_task
from epuck_vrep_compat.learn.worlds import DT_S, Worlds
from epuck_vrep_compat.policy.observation import CAMERA_BINS

METADATA = {"render_modes": ["rgb_array"], "render_fps": int(round(1.0 / DT_S))}


def spaces(layout):
    """(observation space, action space) of one robot for an observation layout."""
    low, high = layout.bounds()
    return (gym.spaces.Box(low.astype(np.float32), high.astype(np.float32), dtype=np.float32),
            gym.spaces.Box(-1.0, 1.0, (2,), dtype=np.float32))


def check_render_mode(render_mode):
    """``render_mode`` if the environments offer it (None or ``rgb_array``), else ValueError."""
    if render_mode not in (None, "rgb_array"):
        raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
    return render_mode


class EpuckEnv(gym.Env):
    """One e-puck learning ``task`` (``obstacle_avoidance``, ``aggregation``,
    ``follow_leader``) in one world; ``noise`` a preset (``real_robot``, ``vrep``, ``ideal``),
    ``robots`` the world's robots (the task's default when None), ``imu`` adds the IMU block,
    ``camera`` the camera row of ``camera_bins`` values, rendered with ``camera_spec`` (a
    ``CameraSpec``; None: the e-puck's default 40 x 40, the ``vrep`` profile's)."""

    metadata = METADATA

    def __init__(self, task: str = "obstacle_avoidance", render_mode=None,
                 noise: str = "real_robot", robots=None, imu: bool = False,
                 episode_steps: int = 400, camera: bool = False,
                 camera_bins: int = CAMERA_BINS, camera_spec=None):
        self.render_mode = check_render_mode(render_mode)
        self.worlds = Worlds(make_task(task, robots, imu, camera, camera_bins), 1, noise,
                             episode_steps=episode_steps, camera=camera_spec)
        self.observation_space, self.action_space = spaces(self.worlds.layout)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.worlds.place(0, self.np_random)
        self.worlds.step(np.zeros((1, len(self.worlds.agents), 2)), rest=[True])
        return self.worlds.agent_obs()[0, 0], self.worlds.info(0)

    def step(self, action):
        rewards = self.worlds.step(np.asarray(action, dtype=float).reshape(1, 1, 2))
        truncated = bool(self.worlds.elapsed[0] >= self.worlds.episode_steps)
        reward = float(rewards[0, self.worlds.agents[0]])
        return self.worlds.agent_obs()[0, 0], reward, False, truncated, self.worlds.info(0)

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        return self.worlds.draw(0)


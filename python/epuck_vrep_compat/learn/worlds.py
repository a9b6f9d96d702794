"""B worlds of one task on the core's ``BatchedWorlds``: arenas drawn per reset from each
world's own generator, the scripted robots' commands, observations through the policy
package's builder (the one ``policy_node`` uses), rewards. The environments are faces on it.

Rows are ``world * R + robot``. A world's reset places its arena and robots and restarts its
noise streams; its first observation is that of a step with the wheels at rest (so the sensors
have read the new arena), taken with the other worlds' next step. The robots' cameras are
rendered (:mod:`epuck_vrep_compat.learn.camera`) only when the layout has the camera block.
"""
from typing import Optional, Sequence

import numpy as np

from epuck_vrep_compat._core import BatchedWorlds
from epuck_vrep_compat.devices.components import CameraSpec
from epuck_vrep_compat.epuck.noise_presets import preset
from epuck_vrep_compat.learn.camera import WorldCameras
from epuck_vrep_compat.learn.render import ArenaPainter
from epuck_vrep_compat.learn.tasks import WALL_RGB, Task
from epuck_vrep_compat.policy import neighbours as nb
from epuck_vrep_compat.policy import observation
from epuck_vrep_compat.policy.controller import braitenberg
from epuck_vrep_compat.scene.epuck_model import default_model

DT_S = 0.05                       # the simulator's step, V-REP's default
SEED_LIMIT = 2 ** 31


class Worlds:
    """B worlds of ``task`` stepped together; ``noise``: a preset name of
    :mod:`epuck_vrep_compat.epuck.noise_presets` (``real_robot``, ``vrep``, ``ideal``);
    ``camera``: the robots' ``CameraSpec`` for a layout with the camera block (None: the
    e-puck's default, the ``vrep`` profile's 40 x 40)."""

    def __init__(self, task: Task, worlds: int, noise: str = "real_robot", dt_s: float = DT_S,
                 episode_steps: int = 400, multi_agent: bool = False,
                 camera: Optional[CameraSpec] = None):
        self.task, self.count, self.dt_s = task, worlds, dt_s
        self.episode_steps = episode_steps
        self.model = default_model()
        self.max_wheel = self.model.max_wheel_speed_rad_s
        self.core = BatchedWorlds(self.model, worlds, task.robots, [0] * worlds)
        self.robots = task.robots
        names = [f"world{b}/robot{r}" for b in range(worlds) for r in range(task.robots)]
        preset(noise).apply(self.core, names)
        learners = task.learners()
        self.agents = learners if multi_agent else learners[:1]
        self.scripted = [r for r in range(task.robots) if r not in self.agents]
        self._avoider = braitenberg(task.layout)
        self._leader = braitenberg(task.layout)
        self._leader.bias[:] = np.arctanh(0.25)        # the leader at a quarter speed
        self.rngs = [np.random.default_rng() for _ in range(worlds)]
        self.cylinders = [[] for _ in range(worlds)]
        self.elapsed = np.zeros(worlds, dtype=np.int64)
        self.obs = np.zeros((worlds * task.robots, task.layout.size))
        # this step's ground truth, read from the core once a step (each read is a copy)
        self.poses = np.zeros((worlds * task.robots, 3))
        self.contact = np.zeros(worlds * task.robots, dtype=bool)
        self._painter = None
        self.cameras = (WorldCameras(self.core, self.model, camera) if task.layout.camera
                        else None)

    @property
    def layout(self):
        return self.task.layout

    def seed(self, world: int, seed: Optional[int]):
        """Restart a world's generator (arenas and noise seeds) from ``seed``."""
        self.rngs[world] = np.random.default_rng(seed)

    def place(self, world: int, rng: Optional[np.random.Generator] = None):
        """A new arena and start in ``world`` from its generator (or ``rng``); the readings
        follow at the next :meth:`step` (with this world's wheels at rest)."""
        rng = self.rngs[world] if rng is None else rng
        cylinders, poses = self.task.arena(rng)
        self.build(world, cylinders, int(rng.integers(SEED_LIMIT)), poses)

    def build(self, world: int, cylinders, seed: int, poses):
        """``world`` anew: the task's walls, ``cylinders`` (:class:`~epuck_vrep_compat.learn.
        tasks.Cylinder`), its noise streams from ``seed``, the robots at ``poses`` (R, 3)."""
        self.core.clear_obstacles(world)
        for centre, half, yaw in self.task.walls():
            self.core.add_box(world, np.array(centre), np.array(half), yaw, np.array(WALL_RGB))
        for c in cylinders:
            self.core.add_cylinder(world, np.array((c.x, c.y, 0.5 * c.height)), c.radius,
                                   c.height, np.array(c.rgb))
        self.cylinders[world] = list(cylinders)
        self.core.reset_world(world, seed)
        for r, (x, y, yaw) in enumerate(poses):
            self.core.set_pose(world, r, float(x), float(y), float(yaw))
        self.elapsed[world] = 0

    def step(self, actions, rest: Sequence[bool] = ()):
        """One step of every world: ``actions`` (B, A, 2) in [-1, 1] for the agents (fractions
        of the top wheel speed), the scripted robots by their controllers, every robot of a
        world with ``rest[world]`` True at rest. Returns the rewards (B, R)."""
        B, R = self.count, self.robots
        wheels = np.zeros((B, R, 2))
        wheels[:, self.agents] = np.clip(np.asarray(actions, float).reshape(
            B, len(self.agents), 2), -1.0, 1.0)
        if self.scripted:
            obs = self.obs.reshape(B, R, -1)[:, self.scripted]
            wheels[:, self.scripted] = self._avoider(obs)
            if self.task.leader:
                wheels[:, 0] = self._leader(self.obs.reshape(B, R, -1)[:, 0])
        resting = np.zeros(B, dtype=bool)
        if len(rest):
            resting[:] = rest
            wheels[resting] = 0.0
        self.core.step(self.dt_s, (wheels * self.max_wheel).reshape(B * R, 2))
        self.elapsed += ~resting
        self.poses = self.core.poses
        self.contact = np.asarray(self.core.in_contact, dtype=bool)
        self.obs = self.observe()
        return self.rewards()

    def observe(self) -> np.ndarray:
        """(N, D) observations of every robot through the policy package's builder."""
        layout, core = self.layout, self.core
        neighbours = None
        if layout.neighbours:
            neighbours = nb.blocks(self.poses, layout.neighbours, layout.neighbour_range_m,
                                   groups=self.count)
        camera = None
        if layout.camera:
            camera = observation.camera_row(self.cameras.render(self.poses), layout.camera_bins)
        return observation.build(layout, core.ranges, core.accel, core.gyro, neighbours, camera)

    def rewards(self) -> np.ndarray:
        B, R = self.count, self.robots
        core = self.core
        wheels = core.wheel_speeds.reshape(B, R, 2)
        obs = self.obs.reshape(B, R, -1)
        poses = self.poses.reshape(B, R, 3)
        contact = self.contact.reshape(B, R)
        return self.task.rewards(wheels, self.max_wheel, obs, poses, contact)

    def agent_obs(self) -> np.ndarray:
        """(B, A, D) float32: the agents' observations."""
        return self.obs.reshape(self.count, self.robots, -1)[:, self.agents].astype(np.float32)

    def info(self, world: int, agent: int = 0) -> dict:
        """The ``info`` of one agent: ``in_contact``, ``pose`` (ground truth x, y, yaw),
        ``elapsed_steps`` of its world's episode."""
        row = world * self.robots + self.agents[agent]
        return {"in_contact": bool(self.contact[row]),
                "pose": self.poses[row].copy(), "elapsed_steps": int(self.elapsed[world])}

    def agent_infos(self) -> dict:
        """:meth:`info` of every agent at once: ``in_contact`` (B, A), ``pose`` (B, A, 3),
        ``elapsed_steps`` (B,), new arrays."""
        B, R = self.count, self.robots
        return {"in_contact": self.contact.reshape(B, R)[:, self.agents],
                "pose": self.poses.reshape(B, R, 3)[:, self.agents],
                "elapsed_steps": self.elapsed.copy()}

    def draw(self, world: int) -> np.ndarray:
        """The RGB array (256, 256, 3) of one world."""
        if self._painter is None:
            self._painter = ArenaPainter([s.yaw_rad for s in self.model.sensors])
        rows = slice(world * self.robots, (world + 1) * self.robots)
        return self._painter.draw(self.cylinders[world], self.poses[rows], self.agents,
                                  self.obs[rows, :8])

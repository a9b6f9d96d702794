"""The learning tasks: each one's arena (walls and seeded obstacles), robots and their starting
poses, which robots learn and which are scripted, the observation layout and the reward.

* ``obstacle_avoidance``: a 1 m square walled arena with 6 cylinders (radius 2 to 5 cm) at
  seeded random places each reset. Reward per robot and step, Floreano and Mondada's (1994)
  fitness ``V (1 - sqrt(dv)) (1 - i)`` in [0, 1]: ``V = |w_l + w_r| / (2 w_max)`` the forward
  speed, ``dv = |w_l - w_r| / (2 w_max)`` the turning, both from the wheels' actual speeds
  (after the motors' clamp and slip), ``i`` the highest IR activation of the observation.
* ``aggregation``: an open 1 m square, 5 robots; the observation adds the 3 nearest
  neighbours within 1.5 m. Reward ``1 - min(1, mean distance to the other robots / 1 m)``.
* ``follow_leader``: a 1 m square; robot 0 is a scripted leader (the Braitenberg avoider at
  a quarter of the top speed: ``worlds.py`` sets its bias to ``arctanh(0.25)``), the learner
  follows it; the observation adds the nearest neighbour within 0.5 m. Reward
  ``exp(-((d - 0.15 m) / 0.1 m)^2)`` for the distance ``d`` to the leader, minus 1 on a step
  that ends in contact.

In the single-robot environments the first learning robot is the agent and the others are
scripted (the Braitenberg avoider, :func:`epuck_vrep_compat.policy.controller.braitenberg`);
in the PettingZoo environment every robot but the leader is an agent.
"""
import math
from dataclasses import dataclass
from typing import List, Tuple

import numpy as np

from epuck_vrep_compat.geometry.fixed_order import libm
from epuck_vrep_compat.policy.observation import CAMERA_BINS, ObservationLayout
from epuck_vrep_compat.scene.scene_file import Arena, Obstacle

ARENA_SIDE_M = 1.0
WALL_THICKNESS_M = 0.02
WALL_HEIGHT_M = 0.05
BODY_RADIUS_M = 0.037
CLEARANCE_M = 0.02                  # between a robot's body and anything at the start
FOLLOW_DISTANCE_M = 0.15
FOLLOW_WIDTH_M = 0.1
# the colours a scene file gives walls and obstacles by default (the camera sees them)
WALL_RGB = Arena().wall_color
OBSTACLE_RGB = Obstacle("", "cylinder", (0.0, 0.0)).color


@dataclass(frozen=True)
class Cylinder:
    """An obstacle of the arena: centre (x, y) and radius [m], standing on the floor, and its
    colour (RGB in 0..1)."""

    x: float
    y: float
    radius: float
    height: float = WALL_HEIGHT_M
    rgb: Tuple[float, float, float] = OBSTACLE_RGB


@dataclass(frozen=True)
class Task:
    """One learning task (see the module's docstring)."""

    name: str
    robots: int
    layout: ObservationLayout
    cylinders: Tuple[int, int] = (0, 0)     # obstacles per reset: (count, 0) or none
    leader: bool = False                    # robot 0 scripted, the others follow it

    def learners(self) -> List[int]:
        """The robots (of a world) that learn: every one but a leader."""
        return list(range(1 if self.leader else 0, self.robots))

    def walls(self):
        """The four walls as (centre (3,), half extents (3,), yaw) around the square."""
        half, t, h = 0.5 * ARENA_SIDE_M, WALL_THICKNESS_M, WALL_HEIGHT_M
        long_wall = (half + t, 0.5 * t, 0.5 * h)
        side_wall = (0.5 * t, half, 0.5 * h)
        return [((0.0, half + 0.5 * t, 0.5 * h), long_wall, 0.0),
                ((0.0, -half - 0.5 * t, 0.5 * h), long_wall, 0.0),
                ((half + 0.5 * t, 0.0, 0.5 * h), side_wall, 0.0),
                ((-half - 0.5 * t, 0.0, 0.5 * h), side_wall, 0.0)]

    def arena(self, rng: np.random.Generator):
        """(cylinders, robot poses (R, 3)) for one reset, drawn from ``rng``."""
        cylinders, poses = [], np.zeros((self.robots, 3))
        for _ in range(self.cylinders[0]):
            radius = float(rng.uniform(0.02, 0.05))
            x, y = _free_spot(rng, radius, cylinders, poses[:0])
            cylinders.append(Cylinder(x, y, radius))
        for r in range(self.robots):
            if self.leader and r == 1:
                poses[1] = _behind(poses[0], cylinders)
                continue
            poses[r, :2] = _free_spot(rng, BODY_RADIUS_M, cylinders, poses[:r])
            poses[r, 2] = rng.uniform(-np.pi, np.pi)
        return cylinders, poses

    def rewards(self, wheels_rad_s, max_wheel_rad_s, observations, poses, contact):
        """(B, R) rewards of every world's robots after a step: wheels (B, R, 2) rad/s,
        observations (B, R, D), poses (B, R, 3), contact (B, R) bool."""
        if self.name == "obstacle_avoidance":
            return floreano_fitness(wheels_rad_s, max_wheel_rad_s, observations[..., :8])
        xy = poses[..., :2]
        distances = np.linalg.norm(xy[:, :, None, :] - xy[:, None, :, :], axis=-1)
        if self.name == "aggregation":
            mean = distances.sum(axis=-1) / max(self.robots - 1, 1)
            return 1.0 - np.minimum(1.0, mean / ARENA_SIDE_M)
        d = distances[..., 0]
        return (libm(math.exp, -np.square((d - FOLLOW_DISTANCE_M) / FOLLOW_WIDTH_M))
                - contact.astype(float))


def scene_cylinders(scene) -> List[Cylinder]:
    """The cylinders of a scene (``scene_file.Scene``) in the learning arena (the tasks' walls:
    same size, thickness, height and colour), to build it in the learning worlds (the parity
    tests compare the two); ValueError for another arena or an obstacle not a cylinder."""
    arena = scene.arena
    if ((tuple(arena.size_m), arena.wall_thickness_m, arena.wall_height_m,
         tuple(arena.wall_color)) != ((ARENA_SIDE_M,) * 2, WALL_THICKNESS_M, WALL_HEIGHT_M,
                                      tuple(WALL_RGB))):
        raise ValueError("the scene's arena is not the learning arena (learn/tasks.py)")
    if any(o.shape != "cylinder" for o in scene.obstacles):
        raise ValueError("the learning arena's obstacles are cylinders")
    return [Cylinder(o.position_m[0], o.position_m[1], o.radius_m, o.height_m, tuple(o.color))
            for o in scene.obstacles]


def floreano_fitness(wheels_rad_s, max_wheel_rad_s, ir_activation) -> np.ndarray:
    """Floreano and Mondada's (1994) ``V (1 - sqrt(dv)) (1 - i)`` per robot: wheels
    (..., 2) rad/s, IR activations (..., 8) -> (...)."""
    w = np.clip(np.asarray(wheels_rad_s, float) / max_wheel_rad_s, -1.0, 1.0)
    v = 0.5 * np.abs(w[..., 0] + w[..., 1])
    dv = 0.5 * np.abs(w[..., 0] - w[..., 1])
    i = np.max(ir_activation, axis=-1)
    return v * (1.0 - np.sqrt(dv)) * (1.0 - i)


def _free_spot(rng, radius, cylinders, poses):
    """A centre in the square at which a disc of ``radius`` clears the walls, the cylinders and
    the robots so far by CLEARANCE_M."""
    limit = 0.5 * ARENA_SIDE_M - radius - CLEARANCE_M
    for _ in range(1000):
        x, y = rng.uniform(-limit, limit, size=2)
        if all(np.hypot(x - c.x, y - c.y) > radius + c.radius + 2 * BODY_RADIUS_M + CLEARANCE_M
               for c in cylinders) and \
                all(np.hypot(x - p[0], y - p[1]) > radius + BODY_RADIUS_M + CLEARANCE_M
                    for p in poses):
            return float(x), float(y)
    raise RuntimeError("no free spot in the arena after 1000 draws")


def _behind(leader_pose, cylinders):
    """The follower's start: FOLLOW_DISTANCE_M behind the leader, facing it, inside the square
    (the follow task's arena has no obstacles)."""
    x, y, yaw = leader_pose
    limit = 0.5 * ARENA_SIDE_M - BODY_RADIUS_M - CLEARANCE_M
    fx = float(np.clip(x - FOLLOW_DISTANCE_M * np.cos(yaw), -limit, limit))
    fy = float(np.clip(y - FOLLOW_DISTANCE_M * np.sin(yaw), -limit, limit))
    return fx, fy, float(np.arctan2(y - fy, x - fx))


TASKS = {      # name: (default robots, neighbours, neighbour range [m], leader)
    "obstacle_avoidance": (1, 0, 0.5, False),
    "aggregation": (5, 3, 1.5, False),
    "follow_leader": (2, 1, 0.5, True),
}


def make_task(name: str, robots=None, imu: bool = False, camera: bool = False,
              camera_bins: int = CAMERA_BINS) -> Task:
    """The task ``name`` (a key of TASKS) with ``robots`` robots (its default when None), the
    IMU and camera blocks in its observation as asked."""
    if name not in TASKS:
        raise ValueError(f"task must be one of {sorted(TASKS)}, got {name!r}")
    default_robots, neighbours, reach_m, leader = TASKS[name]
    layout = ObservationLayout(imu=imu, neighbours=neighbours, neighbour_range_m=reach_m,
                               camera=camera, camera_bins=camera_bins)
    task = Task(name, default_robots if robots is None else robots, layout,
                cylinders=(6, 0) if name == "obstacle_avoidance" else (0, 0), leader=leader)
    if task.robots < (2 if task.leader or name == "aggregation" else 1):
        raise ValueError(f"task {name} needs more robots, got {task.robots}")
    return task

"""The camera row of the learning environments: Gymnasium's check with ``camera=True``, nothing
rendered unless asked, the vector environment's worlds each with its own images, and the
learning worlds' camera images equal, pixel for pixel, to the simulator's (the images behind
the ROS camera topic) for the same state of the learning arena, in the ``vrep`` profile's
camera and in the drivers' 160 x 2 slice."""
import math
import os

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import epuck_vrep_compat.learn  # noqa: F401  (registers the ids)
from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.devices.components import CameraSpec
from epuck_vrep_compat.epuck.cameras import render_robot_cameras
from epuck_vrep_compat.learn import tasks
from epuck_vrep_compat.learn.worlds import Worlds
from epuck_vrep_compat.policy.observation import ObservationLayout, camera_row
from epuck_vrep_compat.scene.scene_file import load_scene
from repo import REPO

LEARN_ARENA = os.path.join(REPO, "worlds", "learn_arena.yaml")
# the drivers' default camera: 160 x 2 rows of the 640 x 480 sensor at zoom 1
# (ros/node/params.py's slice_fov of the e-puck's 0.84 rad)
DRIVERS_CAMERA = CameraSpec(160, 2, vertical_fov_rad=2 * math.atan(math.tan(0.42) * 2 / 480))


def test_check_env_with_the_camera_block():
    env = gym.make("EpuckObstacleAvoidance-v0", camera=True, episode_steps=20)
    check_env(env.unwrapped)
    obs, _ = env.reset(seed=2)
    assert obs.shape == (8 + 16,)
    # the walled arena fills the row (walls, cylinders, robots, lit at least 35 %): no bin
    # is empty or saturated
    assert ((obs[8:] > 0.1) & (obs[8:] < 1.0)).all(), obs[8:]
    plain = gym.make("EpuckObstacleAvoidance-v0")
    assert plain.unwrapped.worlds.cameras is None        # nothing rendered unless asked
    assert plain.reset(seed=2)[0].shape == (8,)


def test_vector_worlds_render_their_own_cameras():
    """World b of the vector environment gives the camera block of gym.make reset with
    seed + b (aggregation: 5 robots a world, the drivers' 160 x 2 camera, 8 bins)."""
    kwargs = dict(camera=True, camera_bins=8, camera_spec=DRIVERS_CAMERA, noise="ideal")
    envs = gym.make_vec("EpuckAggregation-v0", num_envs=2, **kwargs)
    vec_obs, _ = envs.reset(seed=9)
    actions = np.full((2, 2), 0.5)
    vec_next = envs.step(actions)[0]
    for b in range(2):
        env = gym.make("EpuckAggregation-v0", **kwargs)
        obs, _ = env.reset(seed=9 + b)
        assert obs.shape == (8 + 9 + 8,)
        assert np.array_equal(obs, vec_obs[b])
        assert np.array_equal(env.step(actions[b])[0], vec_next[b])
    assert not np.array_equal(vec_obs[0, -8:], vec_obs[1, -8:])


@pytest.mark.parametrize("spec", [None, DRIVERS_CAMERA], ids=["vrep", "drivers"])
def test_learning_worlds_render_the_simulators_camera_images(spec):
    """The learning arena as the simulator builds it and as the environments build it, the
    robots at the simulator's poses: the same rgb8 images, so the same camera block."""
    scene = load_scene(LEARN_ARENA)
    names = ["ePuck0", "ePuck1"]
    sim = build_simulation(scene, SimulationConfig(names, camera=spec))
    sim.epucks.set_wheel_speeds("ePuck0", 3.0, 2.0)
    for _ in range(12):
        sim.step()
    poses = sim.epucks.swarm.poses.copy()
    expected = render_robot_cameras(sim.epucks, names)

    layout = ObservationLayout(camera=True)
    worlds = Worlds(tasks.Task("obstacle_avoidance", 2, layout), 1, noise="ideal",
                    multi_agent=True, camera=spec)
    worlds.build(0, tasks.scene_cylinders(scene), 0, poses)
    worlds.step(np.zeros((1, 2, 2)), rest=[True])
    assert np.array_equal(worlds.poses, poses)
    images = worlds.cameras.render(worlds.poses)
    assert images.shape == expected.shape
    assert np.array_equal(images, expected)
    assert np.array_equal(worlds.obs[:, 8:], camera_row(expected, layout.camera_bins))
    # robot 0 faces the east wall from 3 cm; robot 1 sees robot 0's body, shaded across it
    assert len(np.unique(worlds.obs[1, 8:])) > 3, worlds.obs[1, 8:]


def test_cam0_is_the_robots_left():
    """A black cylinder ahead and to the left of a robot darkens the first bins only."""
    worlds = Worlds(tasks.Task("obstacle_avoidance", 1, ObservationLayout(camera=True)), 1,
                    noise="ideal", camera=None)
    black = tasks.Cylinder(0.2, 0.05, 0.03, rgb=(0.0, 0.0, 0.0))   # 14 degrees to the left
    worlds.build(0, [black], 0, np.zeros((1, 3)))
    worlds.step(np.zeros((1, 1, 2)), rest=[True])
    camera = worlds.obs[0, 8:]
    assert (camera[1:5] == 0.0).all(), camera        # 40 x 40, 0.84 rad: 3 degrees a bin
    assert (camera[8:] > 0.1).all(), camera

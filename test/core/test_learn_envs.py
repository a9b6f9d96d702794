"""The learning environments on the core's BatchedWorlds: Gymnasium's and PettingZoo's own API
checks, determinism per seed, autoreset, the vector environment's worlds equal to the
single-robot environment's, rendering, the tasks' rewards."""
import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import parallel_api_test, parallel_seed_test

import epuck_vrep_compat.learn as learn
from epuck_vrep_compat.learn.parallel import EpuckParallelEnv
from epuck_vrep_compat.learn.tasks import floreano_fitness
from epuck_vrep_compat.policy.controller import braitenberg

STEPS = 40


def rollout(env, actions):
    """(observations, rewards) of a run of ``actions`` from the current state."""
    out_obs, out_rew = [], []
    for a in actions:
        obs, reward, _term, _trunc, _info = env.step(a)
        out_obs.append(np.array(obs))
        out_rew.append(np.array(reward))
    return np.array(out_obs), np.array(out_rew)


@pytest.mark.parametrize("env_id", sorted(learn.ENVIRONMENTS))
def test_gymnasium_check_env(env_id):
    env = gym.make(env_id, render_mode="rgb_array", episode_steps=20)
    check_env(env.unwrapped, skip_render_check=False)
    env.reset(seed=1)
    frame = env.render()
    assert frame.shape == (256, 256, 3) and frame.dtype == np.uint8
    env.close()


def test_check_env_with_the_imu_block():
    env = gym.make("EpuckObstacleAvoidance-v0", imu=True, episode_steps=20)
    check_env(env.unwrapped)
    obs, _ = env.reset(seed=2)
    assert obs.shape == (14,) and obs[10] == pytest.approx(1.0, abs=0.05)   # +g on z at rest


@pytest.mark.parametrize("task", ["obstacle_avoidance", "aggregation", "follow_leader"])
def test_pettingzoo_parallel_api(task):
    parallel_api_test(EpuckParallelEnv(task, episode_steps=30), num_cycles=60)
    parallel_seed_test(lambda: EpuckParallelEnv(task, episode_steps=30))


@pytest.mark.parametrize("env_id", sorted(learn.ENVIRONMENTS))
def test_vector_env_is_deterministic_per_seed(env_id):
    actions = np.random.default_rng(0).uniform(-1, 1, (STEPS, 3, 2))
    runs = []
    for seed in (11, 11, 12):
        envs = gym.make_vec(env_id, num_envs=3)
        obs0, _ = envs.reset(seed=seed)
        obs, rewards = rollout(envs, actions)
        runs.append((obs0, obs, rewards))
        envs.close()
    assert all(np.array_equal(a, b) for a, b in zip(runs[0], runs[1]))
    assert not np.array_equal(runs[0][1], runs[2][1])


def test_vector_world_b_is_the_single_env_seeded_seed_plus_b():
    """World b of ``reset(seed=s)`` draws its arena and noise as ``gym.make(id)`` reset with
    s + b: the same observations and rewards, step by step (noise on)."""
    actions = np.random.default_rng(1).uniform(-1, 1, (STEPS, 2, 2))
    envs = gym.make_vec("EpuckObstacleAvoidance-v0", num_envs=2)
    vec_obs0, _ = envs.reset(seed=40)
    vec_obs, vec_rew = rollout(envs, actions)
    for b in range(2):
        env = gym.make("EpuckObstacleAvoidance-v0")
        obs0, _ = env.reset(seed=40 + b)
        obs, rew = rollout(env, actions[:, b])
        assert np.array_equal(obs0, vec_obs0[b])
        assert np.array_equal(obs, vec_obs[:, b]) and np.array_equal(rew, vec_rew[:, b])


def test_vector_autoreset_next_step():
    envs = gym.make_vec("EpuckObstacleAvoidance-v0", num_envs=2, episode_steps=5)
    envs.reset(seed=3)
    ones = np.ones((2, 2))
    for k in range(4):
        _, _, term, trunc, info = envs.step(ones)
        assert not trunc.any() and not term.any()
    _, _, _, trunc, info = envs.step(ones)
    assert trunc.all() and (info["elapsed_steps"] == 5).all()
    obs, reward, _, trunc, info = envs.step(ones)       # the reset step: action ignored
    assert not trunc.any() and (reward == 0).all() and (info["elapsed_steps"] == 0).all()
    _, _, _, _, info = envs.step(ones)
    assert (info["elapsed_steps"] == 1).all()
    frames = envs.unwrapped.worlds.core.frames
    assert frames.tolist() == [2, 2]                     # the rest step and one more


def test_parallel_env_steps_every_agent_in_one_world():
    env = EpuckParallelEnv("aggregation", robots=4)
    obs, infos = env.reset(seed=5)
    assert sorted(obs) == ["epuck_0", "epuck_1", "epuck_2", "epuck_3"]
    assert obs["epuck_0"].shape == (17,)
    follow = EpuckParallelEnv("follow_leader", robots=3)
    obs, _ = follow.reset(seed=5)
    assert sorted(obs) == ["epuck_1", "epuck_2"]           # robot 0 is the scripted leader
    assert obs["epuck_1"][8] > 0.5                          # the leader 15 cm ahead, in range


def test_floreano_fitness_terms():
    w = 6.283185307
    wheels = np.array([[w, w], [w, -w], [w, w], [0.5 * w, 0.5 * w]])
    ir = np.zeros((4, 8))
    ir[2, 3] = 1.0
    assert floreano_fitness(wheels, w, ir) == pytest.approx([1.0, 0.0, 0.0, 0.5])


def test_braitenberg_avoider_outscores_driving_straight():
    """The shipped hand-set avoider earns more of Floreano's fitness, and touches obstacles
    less, than full speed ahead, over the same eight seeded arenas."""
    scores = {}
    for name in ("straight", "braitenberg"):
        envs = gym.make_vec("EpuckObstacleAvoidance-v0", num_envs=8, episode_steps=300)
        obs, _ = envs.reset(seed=100)
        total, contacts = np.zeros(8), np.zeros(8)
        controller = braitenberg()
        for _ in range(300):
            action = controller(obs) if name == "braitenberg" else np.ones((8, 2))
            obs, reward, _, _, info = envs.step(action)
            total += reward
            contacts += info["in_contact"]
        scores[name] = (total.mean(), contacts.sum())
    assert scores["braitenberg"][0] > scores["straight"][0]
    assert scores["braitenberg"][1] < scores["straight"][1]


def test_world_seeds_option_gives_worlds_the_same_arena():
    envs = gym.make_vec("EpuckObstacleAvoidance-v0", num_envs=3, noise="ideal")
    obs, info = envs.reset(options={"world_seeds": [7, 8, 7]})
    assert np.array_equal(info["pose"][0], info["pose"][2])
    assert not np.array_equal(info["pose"][0], info["pose"][1])
    assert np.array_equal(obs[0], obs[2])
    with pytest.raises(ValueError):
        envs.reset(options={"world_seeds": [1]})


def test_vector_step_refuses_actions_of_another_shape():
    envs = gym.make_vec("EpuckObstacleAvoidance-v0", num_envs=3, noise="ideal")
    envs.reset(seed=1)
    for bad in (np.zeros(6), np.zeros((2, 3)), np.zeros((3, 2, 1))):
        with pytest.raises(ValueError, match=r"actions must be \(3, 2\)"):
            envs.step(bad)
    obs, *_ = envs.step(np.zeros((3, 2)))
    assert obs.shape[0] == 3

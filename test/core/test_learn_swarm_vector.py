"""The swarm batched over B worlds (``EpuckParallelVectorEnv``) and its flat Gymnasium view
(``EpuckFlatVectorEnv``): a world of the batch is the one-world ``EpuckParallelEnv`` seeded with
that world's seed, step for step and across an autoreset (noise on); the dict, array and flat
forms agree; the flat view passes Gymnasium's space and data checks and its vector wrappers."""
import numpy as np
import pytest
from gymnasium.utils.env_checker import data_equivalence
from gymnasium.utils.passive_env_checker import check_action_space, check_observation_space
from gymnasium.wrappers.vector import RecordEpisodeStatistics
from pettingzoo.test import parallel_seed_test

from epuck_vrep_compat.learn.flat_vector import EpuckFlatVectorEnv
from epuck_vrep_compat.learn.parallel import EpuckParallelEnv
from epuck_vrep_compat.learn.parallel_vector import EpuckParallelVectorEnv

TASKS = ["obstacle_avoidance", "aggregation", "follow_leader"]
EPISODE = 12
STEPS = 2 * EPISODE + 3           # two episodes and into the third: two autoresets


def one_world_run(task, seed, actions, **kwargs):
    """[(observations (A, D), rewards (A,), truncations (A,), infos)] of ``EpuckParallelEnv``
    reset with ``seed``, then driven by ``actions`` (T, A, 2); where an episode ended, the next
    entry is ``reset()``'s (rewards 0, no truncation), as the batched env's autoreset step."""
    env = EpuckParallelEnv(task, episode_steps=EPISODE, **kwargs)
    agents = env.possible_agents
    obs, infos = env.reset(seed=seed)
    zeros = np.zeros(len(agents))
    run = [(stack(obs, agents), zeros, zeros.astype(bool), infos)]
    for action in actions:
        if not env.agents:
            obs, infos = env.reset()
            run.append((stack(obs, agents), zeros, zeros.astype(bool), infos))
            continue
        obs, rewards, terms, truncs, infos = env.step(dict(zip(agents, action)))
        assert not any(terms.values())
        run.append((stack(obs, agents), stack(rewards, agents), stack(truncs, agents), infos))
    return run


def stack(values, agents):
    return np.array([values[a] for a in agents])


def assert_world_is_run(batch, world, run, agents):
    """World ``world`` of the batched records ``batch`` equals the one-world ``run``."""
    assert len(batch) == len(run)
    for t, ((obs, rew, trunc, infos), (o, r, tr, i)) in enumerate(zip(batch, run)):
        assert np.array_equal(obs[world], o), f"observations differ at step {t}"
        assert np.array_equal(rew[world], r), f"rewards differ at step {t}"
        assert np.array_equal(trunc[world], tr), f"truncations differ at step {t}"
        for k, agent in enumerate(agents):
            assert np.array_equal(infos["pose"][world, k], i[agent]["pose"])
            assert infos["in_contact"][world, k] == i[agent]["in_contact"]
            assert infos["elapsed_steps"][world] == i[agent]["elapsed_steps"]


def batched_run(env, actions, **reset_kwargs):
    """The records of ``reset_arrays`` then ``step_arrays`` over ``actions`` (T, B, A, 2)."""
    obs, infos = env.reset_arrays(**reset_kwargs)
    zeros = np.zeros((env.num_envs, env.num_agents))
    run = [(obs, zeros, zeros.astype(bool), infos)]
    for action in actions:
        obs, rewards, terms, truncs, infos = env.step_arrays(action)
        assert not terms.any()
        run.append((obs, rewards, truncs, infos))
    return run


@pytest.mark.parametrize("task", TASKS)
def test_one_world_batch_is_the_parallel_env_step_for_step(task):
    env = EpuckParallelVectorEnv(1, task, episode_steps=EPISODE)
    actions = np.random.default_rng(3).uniform(-1, 1, (STEPS, 1, env.num_agents, 2))
    batch = batched_run(env, actions, seed=21)
    assert_world_is_run(batch, 0, one_world_run(task, 21, actions[:, 0]), env.possible_agents)
    assert [t[2].all() for t in batch].count(True) == 2          # two episodes truncated


@pytest.mark.parametrize("task", TASKS)
def test_world_b_is_the_parallel_env_seeded_with_its_seed(task):
    env = EpuckParallelVectorEnv(3, task, episode_steps=EPISODE)
    actions = np.random.default_rng(4).uniform(-1, 1, (STEPS, 3, env.num_agents, 2))
    batch = batched_run(env, actions, seed=30)
    for b in range(3):
        assert_world_is_run(batch, b, one_world_run(task, 30 + b, actions[:, b]),
                            env.possible_agents)
    assert not np.array_equal(batch[1][0][0], batch[1][0][1])    # the worlds differ


def test_pettingzoo_seed_test_applies_to_the_dict_form():
    """PettingZoo's parallel seed test compares two environments with data_equivalence, which
    takes dicts of arrays too (it stops after the first step: ``any`` of a dict is its keys');
    its API test needs a scalar reward per agent, so it is the one-world env's
    (test_learn_envs.py)."""
    parallel_seed_test(lambda: EpuckParallelVectorEnv(3, "aggregation", episode_steps=EPISODE))


def test_world_seeds_option_seeds_each_world():
    env = EpuckParallelVectorEnv(2, "aggregation", episode_steps=EPISODE)
    actions = np.random.default_rng(5).uniform(-1, 1, (8, 2, env.num_agents, 2))
    batch = batched_run(env, actions, options={"world_seeds": [7, 3]})
    for b, seed in enumerate((7, 3)):
        assert_world_is_run(batch, b, one_world_run("aggregation", seed, actions[:, b]),
                            env.possible_agents)
    with pytest.raises(ValueError):
        env.reset(options={"world_seeds": [1]})


def test_dict_and_array_forms_agree():
    envs = [EpuckParallelVectorEnv(2, "aggregation", robots=3) for _ in range(2)]
    agents = envs[0].possible_agents
    assert agents == ["epuck_0", "epuck_1", "epuck_2"] and envs[0].agents == agents
    obs, infos = envs[0].reset(seed=8)
    obs_arr, infos_arr = envs[1].reset_arrays(seed=8)
    assert set(obs) == set(agents) and obs["epuck_1"].shape == (2, 17)
    assert np.array_equal(stack(obs, agents).swapaxes(0, 1), obs_arr)
    assert envs[0].observation_space("epuck_0").contains(obs["epuck_0"])
    assert envs[0].single_observation_space("epuck_0").shape == (17,)
    assert envs[0].action_space("epuck_0").shape == (2, 2)
    assert infos["epuck_2"]["pose"].shape == (2, 3)
    assert np.array_equal(infos["epuck_2"]["pose"], infos_arr["pose"][:, 2])
    actions = np.random.default_rng(6).uniform(-1, 1, (2, 3, 2))
    as_dict = {a: actions[:, k] for k, a in enumerate(agents)}
    for out_dict, out_arr in zip(envs[0].step(as_dict), envs[1].step_arrays(actions)):
        if isinstance(out_arr, dict):
            assert np.array_equal(out_dict["epuck_1"]["pose"], out_arr["pose"][:, 1])
        else:
            assert np.array_equal(stack(out_dict, agents).swapaxes(0, 1), out_arr)
    still = {"epuck_0": actions[:, 0], "epuck_2": actions[:, 2]}     # epuck_1 rests
    actions[:, 1] = 0.0
    for out_dict, out_arr in zip(envs[0].step(still), envs[1].step(actions)):
        for agent in agents:
            assert data_equivalence(out_dict[agent], out_arr[agent], exact=True)
    with pytest.raises(ValueError):
        envs[0].step(np.zeros((2, 2, 2)))
    with pytest.raises(KeyError):
        envs[0].step({"epuck_9": np.zeros((2, 2))})


def test_flat_view_rows_are_world_major_agents():
    flat = EpuckFlatVectorEnv(EpuckParallelVectorEnv(2, "follow_leader", robots=3,
                                                     episode_steps=EPISODE))
    batched = EpuckParallelVectorEnv(2, "follow_leader", robots=3, episode_steps=EPISODE)
    assert flat.num_envs == 4 and flat.single_action_space.shape == (2,)
    obs, infos = flat.reset(seed=9)
    obs_arr, infos_arr = batched.reset_arrays(seed=9)
    assert np.array_equal(obs.reshape(2, 2, -1), obs_arr)
    actions = np.random.default_rng(7).uniform(-1, 1, (EPISODE + 2, 4, 2))
    for action in actions:
        out = flat.step(action)
        ref = batched.step_arrays(action.reshape(2, 2, 2))
        for got, want in zip(out[:4], ref[:4]):
            assert np.array_equal(got, want.reshape(got.shape))
        assert np.array_equal(out[4]["pose"], ref[4]["pose"].reshape(4, 3))
        assert np.array_equal(out[4]["elapsed_steps"], np.repeat(ref[4]["elapsed_steps"], 2))


def test_flat_view_passes_gymnasiums_vector_checks():
    def make():
        return EpuckFlatVectorEnv(EpuckParallelVectorEnv(3, "aggregation", robots=4,
                                                         episode_steps=EPISODE))
    env = make()
    check_observation_space(env.single_observation_space)
    check_action_space(env.single_action_space)
    assert env.observation_space.shape == (12,) + env.single_observation_space.shape
    assert env.metadata["autoreset_mode"].value == "NextStep"
    obs, infos = env.reset(seed=1)
    assert env.observation_space.contains(obs)
    first = obs.copy()
    env.action_space.seed(2)
    records = []
    for _ in range(EPISODE + 2):
        step = env.step(env.action_space.sample())
        assert env.observation_space.contains(step[0]) and step[1].shape == (12,)
        assert step[2].dtype == bool and step[3].dtype == bool
        records.append(step)
    assert np.array_equal(first, obs)                 # returned data is not reused
    again = make()
    assert data_equivalence(again.reset(seed=1), (first, infos), exact=True)
    env.action_space.seed(2)
    for step in records:
        assert data_equivalence(again.step(env.action_space.sample()), step, exact=True)
    assert records[EPISODE - 1][3].all() and not records[EPISODE][3].any()
    assert (records[EPISODE][1] == 0).all()           # the reset step
    stats = RecordEpisodeStatistics(make())
    stats.reset(seed=1)
    for _ in range(EPISODE):
        _, _, _, _, info = stats.step(np.zeros((12, 2)))
    assert info["_episode"].all() and (info["episode"]["l"] == EPISODE).all()


def test_render_gives_one_frame_a_world():
    env = EpuckParallelVectorEnv(2, "aggregation", render_mode="rgb_array")
    env.reset(seed=1)
    frames = EpuckFlatVectorEnv(env).render()
    assert len(frames) == 2 and frames[0].shape == (256, 256, 3)
    assert EpuckParallelVectorEnv(1, "aggregation").render() is None

"""Dimensions, names, determinism, and the rsl-rl / Gymnasium adapters."""

import numpy as np
import pytest
import torch

from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.multi_object import MultiObjectEnv
from mobilemani_rl.envs.vecenv import GymVectorEnv, RslRlVecEnv
from mobilemani_rl.rl.factory import policy_objects
from mobilemani_rl.utils.errors import UnknownNameError


@pytest.mark.parametrize(("robot", "obs_dim", "act_dim"), [("g1", 146, 7), ("xhand", 223, 18)])
def test_observation_and_action_dimensions(robot, obs_dim, act_dim):
    env = MobileManiEnv(EnvCfg(num_envs=4, task=TaskCfg(robot=robot)))
    obs = env.reset()
    assert env.num_obs == obs_dim and env.num_actions == act_dim
    assert obs.shape == (4, obs_dim) and obs.dtype == np.float32
    result = env.step(np.random.default_rng(0).uniform(-1, 1, (4, act_dim)))
    assert result.obs.shape == (4, obs_dim)
    assert np.all(np.abs(result.obs) <= 10.0)


def test_observation_layout_time_action_and_object_terms():
    env = MobileManiEnv(EnvCfg(num_envs=2))
    env.reset()
    action = np.tile([0.1, -0.2, 0.3, 0.0, 0.05, -0.05, 0.5], (2, 1))
    obs = env.step(action).obs
    # Time encoding of step 1: slot 0 = sin(1), slot 1 = cos(1).
    np.testing.assert_allclose(obs[:, :2], [[np.sin(1.0), np.cos(1.0)]] * 2, atol=1e-6)
    np.testing.assert_allclose(obs[:, 30:37], action, atol=1e-6)
    # Object block (last 9): grasp position, grasp Euler, goal - grasp.
    np.testing.assert_allclose(obs[:, -9:-6], env.frames.grasp_pos, atol=1e-5)
    np.testing.assert_allclose(obs[:, -3:], env.goal_pos - env.frames.grasp_pos, atol=1e-5)


@pytest.mark.parametrize(
    ("task", "message"),
    [
        (TaskCfg(robot="h1"), "valid robots: g1, xhand"),
        (TaskCfg(object="nope/0000"), "valid objects:"),
        (TaskCfg(skill="fly"), "valid skills: close, open, pick, pull, push"),
        (TaskCfg(object="test/can", skill="open"), "valid skills for it: pick"),
    ],
)
def test_unknown_names_list_valid_choices(task, message):
    with pytest.raises(UnknownNameError, match=message):
        MobileManiEnv(EnvCfg(num_envs=1, task=task))


def _rollout(seed: int, steps: int = 40, physics_threads: int = 0) -> np.ndarray:
    cfg = EnvCfg(num_envs=3, seed=seed)
    cfg.physics.nthread = physics_threads
    env = MobileManiEnv(cfg)
    env.reset()
    rng = np.random.default_rng(123)
    return np.stack([env.step(rng.uniform(-1, 1, (3, 7))).obs for _ in range(steps)])


def test_same_seed_same_rollout():
    first, second = _rollout(7), _rollout(7)
    np.testing.assert_array_equal(first, second)
    assert not np.array_equal(first, _rollout(8))


def test_the_physics_thread_count_does_not_change_a_rollout():
    """Each env steps alone, so `env.physics.nthread` says where a run computes (a resumed run may change it),
    not what it learns."""
    np.testing.assert_array_equal(_rollout(7, physics_threads=1), _rollout(7, physics_threads=2))


def test_rsl_rl_vecenv_interface():
    vec = RslRlVecEnv(MobileManiEnv(EnvCfg(num_envs=4)))
    obs = vec.get_observations()
    assert obs.batch_size == torch.Size([4]) and obs["policy"].shape == (4, 146)
    vec.episode_length_buf = torch.full((4,), 298)
    obs, rewards, dones, extras = vec.step(torch.zeros(4, 7))
    assert rewards.shape == (4,) and rewards.dtype == torch.float32
    # Episode step 299 reaches the time limit: every env times out and is reset.
    assert dones.all() and extras["time_outs"].all()
    assert "/reward/diff_hand_object" in extras["log"] and "/episode/success_flag" in extras["log"]


def test_rsl_rl_vecenv_sets_episode_lengths_of_a_multi_object_env():
    """rsl-rl's random initial episode lengths reach every object's env: episodes of a category policy end at
    different steps, so every PPO iteration has finished episodes to report (not success=nan)."""
    vec = RslRlVecEnv(
        MultiObjectEnv(EnvCfg(num_envs=4, task=TaskCfg(object="laptop")), policy_objects("laptop", 2))
    )
    vec.episode_length_buf = torch.tensor([298, 0, 0, 298])
    np.testing.assert_array_equal(vec.episode_length_buf.numpy(), [298, 0, 0, 298])
    _, _, dones, extras = vec.step(torch.zeros(4, 7))
    assert dones.tolist() == [True, False, False, True]
    assert extras["log"]["/episode/success_flag"].shape == (2,)


def test_gymnasium_vector_adapter_same_step_autoreset():
    env = GymVectorEnv(MobileManiEnv(EnvCfg(num_envs=2)))
    obs, _ = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    env.env.episode_length_buf[:] = 298
    obs, reward, terminated, truncated, infos = env.step(env.action_space.sample())
    assert truncated.all() and not terminated.any()
    assert infos["_final_obs"].all() and infos["final_obs"][0].shape == (146,)

"""The env takes exactly one action row per env; NaN entries are applied as 0 and counted, never hidden."""

import re

import numpy as np
import pytest
import torch

from mobilemani_rl.envs.actions import checked_actions
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.rollout import run_first_episodes
from mobilemani_rl.envs.vecenv import RslRlVecEnv
from mobilemani_rl.scripted.policy import ScriptedPolicy
from mobilemani_rl.utils.errors import InputError


def test_checked_actions_clamp_zero_nan_and_count_them():
    raw = np.array([[2.0, np.nan, -3.0, 0.5, 0.0, 0.0, np.nan], [0.1] * 7])
    actions, nan = checked_actions(raw, 2, 7)
    assert actions[0].tolist() == [1.0, 0.0, -1.0, 0.5, 0.0, 0.0, 0.0] and nan.tolist() == [2, 0]
    for shape in [(7,), (2, 1), (1, 7), (2, 8)]:
        with pytest.raises(ValueError, match=r"\(num_envs, action_dim\) = \(2, 7\)"):
            checked_actions(np.zeros(shape), 2, 7)


def test_env_refuses_a_wrong_width_and_rollouts_report_nan_actions():
    env = MobileManiEnv(
        EnvCfg(num_envs=3, seed=0, episode_length=5, task=TaskCfg(object="test/box", skill="open"))
    )
    env.reset(seed=0)
    with pytest.raises(ValueError, match="got \\(3, 6\\)"):
        env.step(np.zeros((3, 6)))

    def half_nan() -> np.ndarray:
        actions = np.zeros((3, env.num_actions))
        actions[1, :2] = np.nan
        return actions

    stats = run_first_episodes(env, half_nan, seed=0)
    assert stats.nan_actions.tolist() == [0, 2 * stats.length[1], 0]
    assert stats.summary()["nan_action_entries"] == 2 * stats.length[1]


def test_python_api_misuse_names_the_argument_before_the_simulator_sees_it():
    """Each of these reached a library's message naming no argument: MuJoCo's constructor for 2.5 envs,
    numpy's "expected non-negative integer" for a seed, an AttributeError for a step or a scripted action
    before any reset."""
    for bad_count in (2.5, "2"):
        with pytest.raises(InputError, match=f"whole numbers of at least 1: env.num_envs={bad_count!r}"):
            MobileManiEnv(EnvCfg(num_envs=bad_count))
    with pytest.raises(InputError, match=r"env.seed=1.5 \(an integer >= 0\)"):
        MobileManiEnv(EnvCfg(num_envs=1, seed=1.5))
    env = MobileManiEnv(EnvCfg(num_envs=2, task=TaskCfg(object="test/box", skill="open")))
    for act_before_reset in (lambda: env.step(np.zeros((2, env.num_actions))), ScriptedPolicy(env)):
        with pytest.raises(RuntimeError, match=r"call reset\(\) before the first step\(\) or action"):
            act_before_reset()
    # a list is Gymnasium's per-env seeds, which the batch's one generator cannot honour
    for bad_seed in (-1, 1.5, "a", [0, 1]):
        with pytest.raises(InputError, match=re.escape(f"reset(seed={bad_seed!r}): the seed must be an int")):
            env.reset(seed=bad_seed)
    env.reset(seed=np.int64(3))  # numpy's own integers are seeds too
    assert env.step(np.zeros((2, env.num_actions))).obs.shape == (2, env.num_obs)
    with pytest.raises(
        InputError, match=r"EnvCfg\(task=...\) takes a TaskCfg\(robot, object, skill, scene\), not a dict"
    ):
        MobileManiEnv(EnvCfg(num_envs=1, task={"robot": "g1"}))
    # the rsl-rl view takes rsl-rl's tensors and the numpy batches of the Gymnasium one alike
    rsl_env = RslRlVecEnv(env)
    for actions in (torch.zeros((2, env.num_actions)), np.zeros((2, env.num_actions))):
        assert rsl_env.step(actions)[0]["policy"].shape == (2, env.num_obs)
    with pytest.raises(ValueError, match=r"actions must have shape \(num_envs, action_dim\)"):
        rsl_env.step(np.zeros((3, env.num_actions)))

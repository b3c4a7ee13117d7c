"""Warm start of a PPO teacher from the scripted policy: labels, returns, cloning and its use in training."""

import json

import numpy as np
import pytest
import torch
from checkout import ROOT
from hydra import compose, initialize_config_dir
from tensordict import TensorDict

from mobilemani_rl.rl.config import RLCfg
from mobilemani_rl.rl.factory import build_runner
from mobilemani_rl.rl.run_dir import latest_checkpoint
from mobilemani_rl.rl.runner import MobileManiRunner
from mobilemani_rl.rl.train import train
from mobilemani_rl.rl.warm_start import collect, discounted_returns, warm_start
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.errors import ConfigMismatchError

TINY = [
    "rl/ppo=tiny",
    "task.object=test/can",
    "task.skill=pick",
    "rl.ppo.warm_start.episodes=8",
    "rl.ppo.warm_start.epochs=30",
    "rl.ppo.warm_start.mini_batch_size=256",
]


def compose_rl(overrides: list[str]):
    with initialize_config_dir(config_dir=str(ROOT / "conf"), version_base="1.3"):
        return compose(config_name="rl", overrides=overrides)


def test_discounted_returns_sum_each_episodes_future_rewards():
    rewards = np.array([[1.0, 2.0], [1.0, 0.0], [1.0, 0.0]])  # env 1's episode ended after one step
    returns = discounted_returns(rewards, gamma=0.5)
    np.testing.assert_allclose(returns, [[1.75, 2.0], [1.5, 0.0], [1.0, 0.0]])


@pytest.fixture(scope="module")
def tiny_runner():
    cfg = compose_rl(TINY)
    return build_runner(cfg, run_dir=None), to_dataclass(cfg, RLCfg).rl.ppo


def test_collected_labels_are_scripted_actions_of_every_step(tiny_runner):
    runner, ppo = tiny_runner
    env = runner.env.env
    demos = collect(env, episodes=12, noise=0.3, seed=5, gamma=ppo.gamma)
    assert demos.episodes == 16  # rounded up to two batches of 8 envs
    assert demos.obs.shape == (len(demos.actions), env.num_obs) and demos.actions.shape[1] == env.num_actions
    assert len(demos.returns) == len(demos.obs) and demos.successes > 0
    # Far from the can the distance penalties dominate; holding it at the goal earns the bonuses.
    assert demos.returns.min() < 0.0 < demos.returns.max()
    assert np.all(np.abs(demos.actions) <= 1.0)  # labels are the clipped scripted actions, not the noisy ones
    assert set(np.unique(demos.actions[:, 6])) <= {-1.0, 1.0}  # the gripper is scripted open or closed
    assert 8 * 2 <= len(demos.obs) <= 16 * env.max_episode_length


def test_warm_start_clones_the_scripted_actions_and_sets_the_noise(tiny_runner):
    runner, ppo = tiny_runner
    actor, critic, env = runner.alg.actor, runner.alg.critic, runner.env.env
    held_out = collect(env, episodes=8, noise=0.3, seed=77, gamma=ppo.gamma)
    x = TensorDict({"policy": torch.from_numpy(held_out.obs)}, batch_size=[len(held_out.obs)])

    def error() -> float:
        with torch.no_grad():
            return float(((actor(x).numpy() - held_out.actions) ** 2).mean())

    before = error()
    info = warm_start(actor, critic, env, ppo.warm_start, ppo.gamma)
    assert info["episodes"] == 8 and info["actor_loss"][1] < 0.5 * info["actor_loss"][0]
    assert info["critic_loss"][1] < info["critic_loss"][0]
    assert error() < 0.5 * before  # also on episodes it was not fitted to
    std = actor.distribution.std_param
    assert torch.equal(std, torch.full_like(std, ppo.warm_start.noise_std))
    assert np.all(env.env_times == 0)  # left at fresh episodes


def test_training_starts_from_the_warm_start_once(tmp_path):
    run_dir = tmp_path / "run"
    overrides = [*TINY, f"run_dir={run_dir}", "rl.ppo.max_iterations=2"]
    train(compose_rl(overrides))
    info = json.loads((run_dir / "warm_start.json").read_text())
    assert info["episodes"] == 8 and info["steps"] > 0 and (run_dir / "result.json").exists()
    # A resumed run continues from its checkpoint instead of cloning again.
    (run_dir / "result.json").unlink()
    written = (run_dir / "warm_start.json").stat().st_mtime_ns
    train(compose_rl(overrides))
    assert (run_dir / "warm_start.json").stat().st_mtime_ns == written and (run_dir / "result.json").exists()


def _interrupt(*args, **kwargs):
    raise KeyboardInterrupt  # what Ctrl-C raises wherever the run is


def _must_not_run(*args, **kwargs):
    raise AssertionError("the finished warm start was redone")


def test_a_finished_warm_start_survives_an_interrupt_and_an_unfinished_one_leaves_nothing(
    tmp_path, monkeypatch, capsys
):
    run_dir = tmp_path / "run"
    overrides = [*TINY, f"run_dir={run_dir}", "rl.ppo.max_iterations=1"]
    with monkeypatch.context() as patch, pytest.raises(KeyboardInterrupt):
        patch.setattr("mobilemani_rl.rl.warm_start.fit", _interrupt)  # Ctrl-C after collection, while fitting
        train(compose_rl(overrides))
    assert not list(run_dir.glob("warm_start*")) and latest_checkpoint(run_dir) is None
    # The warm start reports its totals with an ETA (tqdm bars on stderr).
    assert "warm start: 8 scripted episodes: 100%" in capsys.readouterr().err
    with monkeypatch.context() as patch, pytest.raises(KeyboardInterrupt):
        patch.setattr(MobileManiRunner, "learn", _interrupt)  # Ctrl-C in PPO before its first checkpoint
        train(compose_rl(overrides))
    assert (run_dir / "warm_start.json").exists() and (run_dir / "warm_start.pt").exists()
    assert not list(run_dir.glob("*.tmp")) and latest_checkpoint(run_dir) is None
    assert "warm start: fitting the critic: 100%|" in capsys.readouterr().err
    with pytest.raises(ConfigMismatchError):  # the kept warm start belongs to the saved config
        train(compose_rl([*overrides, "rl.ppo.warm_start.epochs=5"]))
    monkeypatch.setattr("mobilemani_rl.rl.train.warm_start", _must_not_run)
    train(compose_rl(overrides))
    assert f"resuming {run_dir} from its finished warm start (warm_start.pt)" in capsys.readouterr().out
    assert (run_dir / "result.json").exists()


def test_multi_object_env_collects_episodes_of_every_object():
    cfg = compose_rl(["rl/ppo=tiny", "task.object=laptop", "objects_per_policy=2"])
    env = build_runner(cfg, run_dir=None).env.env
    demos = collect(env, episodes=4, noise=0.3, seed=5, gamma=0.99)
    assert [part.num_envs for part in env.envs] == [4, 4] and demos.episodes == 8
    assert len(demos.obs) >= 8 and demos.actions.shape == (len(demos.obs), env.num_actions)

"""The step profile: every stage's exclusive share, and timers that leave the env's behaviour unchanged."""

import numpy as np
import torch

from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.step_profile import STAGES, StageTimer, profile_step, profile_table


def make_env() -> MobileManiEnv:
    task = TaskCfg(robot="g1", object="test/box", skill="open")
    return MobileManiEnv(EnvCfg(num_envs=4, seed=3, task=task))


def test_nested_timed_calls_count_in_their_own_stage_only(monkeypatch):
    timer = StageTimer()
    clock = iter([0.0, 1.0, 3.0, 10.0])  # outer starts, inner starts, inner ends, outer ends
    inner = timer.wrap(lambda: None, "physics")
    outer = timer.wrap(inner, "rest")
    monkeypatch.setattr("mobilemani_rl.envs.step_profile.time.perf_counter", lambda: next(clock))
    outer()
    monkeypatch.undo()
    assert timer.totals["physics"] == 2.0 and timer.totals["rest"] == 8.0


def test_profile_shares_cover_the_step_and_the_timers_change_nothing():
    plain, profiled = make_env(), make_env()
    profile = profile_step(profiled, steps=30)
    shares = [profile[s] for s in STAGES]
    assert all(s >= 0 for s in shares) and abs(sum(shares) - 1.0) < 0.01
    assert profile["physics"] > 0 and profile["adapter_steps_per_s"] > 0
    # the same seeded actions on an env without timers: the same observations after the same 31 steps
    generator = torch.Generator().manual_seed(0)
    actions = [torch.rand(4, plain.num_actions, generator=generator) * 2 - 1 for _ in range(64)]
    plain.reset()
    for k in [0, *range(30)]:
        plain.step(actions[k % 64].numpy())
    assert np.array_equal(plain.obs, profiled.obs)
    assert "| g1 | 4 |" in profile_table([{"robot": "g1", "num_envs": 4, "profile": profile}])

"""The interface of a batch of envs, which one task's `MobileManiEnv` and a category's `MultiObjectEnv` both
offer: what the rsl-rl and Gymnasium adapters, the PPO runner, the warm start and a teacher's policy use."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.mobilemani_env import StepResult


class BatchedEnv(Protocol):
    cfg: EnvCfg
    num_envs: int
    num_actions: int
    num_obs: int
    max_episode_length: int
    obs: np.ndarray | None  # the current observation; None before the first reset
    episode_length_buf: np.ndarray  # steps into each env's episode (a trainer may randomise them)

    def reset(self, seed: int | None = None) -> np.ndarray: ...

    def step(self, actions: np.ndarray) -> StepResult: ...

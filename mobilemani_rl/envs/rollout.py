"""Run one episode in every env of a batch and collect its latched success and reward breakdown."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from mobilemani_rl.envs.mobilemani_env import MobileManiEnv, StepResult

Policy = Callable[[], np.ndarray]  # reads the env it was built on, returns (num_envs, num_actions)


@dataclass
class EpisodeStats:
    success: np.ndarray  # (num_envs,) bool
    length: np.ndarray  # (num_envs,) control steps
    nan_actions: np.ndarray  # (num_envs,) NaN action entries the policy sent (each applied as 0)
    reward_terms: dict[str, np.ndarray] = field(default_factory=dict)  # per-episode sums of weighted terms

    def summary(self) -> dict:
        return {
            "episodes": int(self.success.size),
            "success_rate": float(self.success.mean()),
            "mean_length": float(self.length.mean()),
            "reward_terms": {k: float(v.mean()) for k, v in self.reward_terms.items()},
            "mean_return": float(sum(v for v in self.reward_terms.values()).mean())
            if self.reward_terms
            else 0.0,
            "nan_action_entries": int(self.nan_actions.sum()),
        }


def run_first_episodes(
    env: MobileManiEnv, policy: Policy, seed: int, on_step: Callable[[StepResult], None] | None = None
) -> EpisodeStats:
    """Reset with `seed`, step until every env has finished its first episode, and collect its statistics.

    An episode succeeds if its grasp point came within the success threshold of the goal at any step, as the
    reference's latched `success_flag`. Envs that finish early keep stepping (batched) but stop counting.
    """
    env.reset(seed=seed)
    n = env.num_envs
    success = np.zeros(n, dtype=bool)
    running = np.ones(n, dtype=bool)
    length = np.zeros(n, dtype=np.int64)
    sums: dict[str, np.ndarray] = {}
    nan_actions = np.zeros(n, dtype=np.int64)
    for _ in range(env.max_episode_length):
        result = env.step(policy())
        if on_step is not None:
            on_step(result)
        for name, values in result.reward_terms.items():
            sums.setdefault(name, np.zeros(n))[running] += values[running]
        length[running] += 1
        nan_actions[running] += result.nan_actions[running]
        ended = np.zeros(n, dtype=bool)
        ended[result.done_ids] = True
        newly = ended & running
        success[newly] = result.success_flag[newly]
        running &= ~ended
        if not running.any():
            break
    return EpisodeStats(success, length, nan_actions, sums)


def first_episode_success(
    env: MobileManiEnv, policy: Policy, seed: int, on_step: Callable[[StepResult], None] | None = None
) -> np.ndarray:
    return run_first_episodes(env, policy, seed, on_step).success

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


class FirstEpisodes:
    """The first episode of every env of a batch, one control step at a time: `reset(seed)`, then `step` until
    `finished`. The one definition of an evaluation episode's start, length and success, shared by
    `run_first_episodes` and the env LeRobot's tools step (integrations/lerobot_env_mobilemanibench).

    An episode succeeds if its grasp point came within the success threshold of the goal at any step, as the
    reference's latched `success_flag`. Envs that finish early keep stepping (batched) but stop counting.
    """

    def __init__(self, env: MobileManiEnv) -> None:
        self.env = env

    def reset(self, seed: int | None) -> None:
        self.env.reset(seed=seed)
        n = self.env.num_envs
        self.success = np.zeros(n, dtype=bool)
        self.running = np.ones(n, dtype=bool)
        self.length = np.zeros(n, dtype=np.int64)
        self.nan_actions = np.zeros(n, dtype=np.int64)
        self.sums: dict[str, np.ndarray] = {}
        self.steps = 0

    @property
    def finished(self) -> bool:
        return self.steps >= self.env.max_episode_length or not self.running.any()

    def step(self, actions: np.ndarray) -> StepResult:
        result = self.env.step(actions)
        running = self.running
        for name, values in result.reward_terms.items():
            self.sums.setdefault(name, np.zeros(len(running)))[running] += values[running]
        self.length[running] += 1
        self.nan_actions[running] += result.nan_actions[running]
        ended = np.zeros(len(running), dtype=bool)
        ended[result.done_ids] = True
        newly = ended & running
        self.success[newly] = result.success_flag[newly]
        self.running = running & ~ended
        self.steps += 1
        return result

    def stats(self) -> EpisodeStats:
        return EpisodeStats(self.success, self.length, self.nan_actions, self.sums)


def run_first_episodes(
    env: MobileManiEnv, policy: Policy, seed: int, on_step: Callable[[StepResult], None] | None = None
) -> EpisodeStats:
    """Reset with `seed`, step until every env has finished its first episode (FirstEpisodes), and collect
    its statistics."""
    episodes = FirstEpisodes(env)
    episodes.reset(seed)
    while not episodes.finished:
        result = episodes.step(policy())
        if on_step is not None:
            on_step(result)
    return episodes.stats()


def first_episode_success(
    env: MobileManiEnv, policy: Policy, seed: int, on_step: Callable[[StepResult], None] | None = None
) -> np.ndarray:
    return run_first_episodes(env, policy, seed, on_step).success

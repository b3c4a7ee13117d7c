"""Run one episode in every env of a batch and collect its latched success."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from mobilemani_rl.envs.mobilemani_env import MobileManiEnv, StepResult

Policy = Callable[[], np.ndarray]  # reads the env it was built on, returns (num_envs, num_actions)


def first_episode_success(env: MobileManiEnv, policy: Policy, seed: int,
                          on_step: Callable[[StepResult], None] | None = None) -> np.ndarray:
    """Reset with `seed`, step until every env has finished its first episode, and return (num_envs,) successes.

    An episode succeeds if its grasp point came within the success threshold of the goal at any step, as the
    reference's latched `success_flag`.
    """
    env.reset(seed=seed)
    success = np.zeros(env.num_envs, dtype=bool)
    finished = np.zeros(env.num_envs, dtype=bool)
    for _ in range(env.max_episode_length):
        result = env.step(policy())
        if on_step is not None:
            on_step(result)
        ended = np.zeros(env.num_envs, dtype=bool)
        ended[result.done_ids] = True
        newly = ended & ~finished
        success[newly] = result.success_flag[newly]
        finished |= ended
        if finished.all():
            break
    return success

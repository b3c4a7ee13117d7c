"""One evaluation batch: a policy's episodes in one env batch, through observations, chunks and the ensemble.

Stepping and success accounting are mobilemani_rl.envs.rollout's (the first episode of every env, latched
success), so a privileged policy scored here matches its own evaluation under the same env config and seed.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable

import numpy as np

from mobilemani_rl.envs.base_frame import Convention, action_to_world
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv, StepResult
from mobilemani_rl.envs.rollout import EpisodeStats, run_first_episodes
from mobilemani_rl.envs.tasks import Combination, recording_env_cfg
from mobilemani_vla.eval.observe import ObservationBuilder
from mobilemani_vla.eval.policies.base import EvalPolicy
from mobilemani_vla.model.ensemble import ChunkExecutor, EnsembleCfg


def batch_seed(combo: Combination, first_episode: int) -> int:
    """The env seed of a batch of `combo`'s episodes whose first episode is numbered `first_episode`.
    Episode e of an evaluation with seed s is numbered s + e, as `lerobot-eval --seed=s` numbers its
    episodes, so a batch of the same size starting at the same number replays the same start states in our
    harness and in LeRobot's (integrations/lerobot_env_mobilemanibench)."""
    # "/0" in the key keeps the seeds that every recorded evaluation's first batch was run with
    return (first_episode * 1_000_003 + zlib.crc32(f"{combo.name}/0".encode())) % 2**31


def episode_env(params: EnvCfg, combo: Combination, num_envs: int, seed: int) -> MobileManiEnv:
    """The env batch that runs `combo`'s evaluation episodes: `params` with its task and recording resets
    (the realistic scenes the dataset was recorded in)."""
    task = TaskCfg(combo.robot, combo.object_id, combo.skill, combo.scene)
    return MobileManiEnv(recording_env_cfg(params, task, num_envs, seed))


def run_batch(
    env: MobileManiEnv,
    policy: EvalPolicy,
    seed: int,
    instruction: str,
    ensemble: EnsembleCfg,
    image_size: tuple[int, int] = (224, 224),
    convention: Convention = "conjugate",
    on_step: Callable[[StepResult], None] | None = None,
) -> EpisodeStats:
    """Reset `env` with `seed` and run the first episode of each of its envs under `policy`."""
    height, width = image_size
    builder = ObservationBuilder(env, policy.inputs, instruction, width, height)
    executor = ChunkExecutor(ensemble, env.num_envs)
    active = np.ones(env.num_envs, dtype=bool)

    def act() -> np.ndarray:
        actions = executor(policy.act(builder(active.copy())))
        if policy.action_frame == "base":
            actions = action_to_world(actions, env.frames.base_quat, convention)
        return actions

    def after_step(result: StepResult) -> None:
        executor.reset(result.done_ids)  # the reference resets the ensembler when an episode ended
        active[result.done_ids] = False
        if on_step is not None:
            on_step(result)

    policy.start(env, seed)
    try:
        return run_first_episodes(env, act, seed, after_step)
    finally:
        builder.close()

"""Closed-loop evaluation of any policy on MobileManiBench (docs/reference.md, "VLA evaluation").

  python -m mobilemani_vla.eval.evaluate robot=g1 \\
      policy.checkpoint=outputs/vla/g1/default/tiny/checkpoints/step_X
  python -m mobilemani_vla.eval.evaluate eval/policy=scripted eval/protocol=ablation eval/split=seen_unseen
  make eval ROBOT=g1 CHECKPOINT=<dir>

Protocol: every (object, skill, scene) combination of the selected object split x scene split (default: test
objects x test scenes), `subset.episodes` episodes each (10), 300 control steps, success when the grasp point
comes within 5 cm of the goal. Episodes of a combination run as env batches of `episodes_per_batch` (at most
`subset.episodes`); each batch's env seed comes from (robot, object, skill, scene) and the number of its first
episode, seed + e (harness.batch_seed), so episode e of a combination is always the same start state,
whichever of the `workers` processes runs it, and `lerobot-eval --env.type=mobilemanibench --seed=<seed>`
with the same batch size replays it. The total is
printed up front, and every batch's line ends with the episodes done so far and an ETA. Results:
<output_dir>/<robot>/<name>/<split>.jsonl (one record per episode, resumable), a summary JSON next to it (per
skill, per category), and head-camera MP4s of the first `video_episodes` episodes. A run directory that
cannot be written (a file in the way, a read-only file system) stops before the policy is built.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # this command renders offscreen; mujoco reads it when imported

import json
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import hydra
from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.assets.robots import get_robot
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv, StepResult
from mobilemani_rl.envs.rollout import EpisodeStats
from mobilemani_rl.envs.tasks import Combination, select_combinations
from mobilemani_rl.envs.video import HeadCameraRecorder
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import changed_values, to_dataclass
from mobilemani_rl.utils.errors import ConfigMismatchError, InputError
from mobilemani_rl.utils.io import check_writable, read_json, write_json_atomic
from mobilemani_rl.utils.process_pool import run_in_pool
from mobilemani_rl.utils.progress import Progress
from mobilemani_rl.utils.video_logs import quiet_video_libraries
from mobilemani_vla.eval.config import DEFAULT_IMAGE_SIZE, EvalCfg, PolicyCfg
from mobilemani_vla.eval.harness import batch_seed, episode_env, run_batch
from mobilemani_vla.eval.policies.base import EvalPolicy
from mobilemani_vla.eval.policies.factory import build_policy
from mobilemani_vla.eval.results import ResultsFile, read_records, summarize, summary_path
from mobilemani_vla.model.ensemble import check_action_index


def run_dir(cfg: EvalCfg) -> Path:
    return Path(cfg.output_dir) / cfg.robot / cfg.name


def block_env(cfg: EvalCfg, combo: Combination, block: int) -> tuple[MobileManiEnv, int]:
    """The env batch of one evaluation block and the seed the harness resets it with."""
    seed = batch_seed(combo, cfg.seed + block * cfg.batch_size)
    return episode_env(cfg.env, combo, cfg.batch_size, seed), seed


def run_block(
    cfg: EvalCfg,
    policy: EvalPolicy,
    combo: Combination,
    env: MobileManiEnv,
    seed: int,
    on_step: Callable[[StepResult], None] | None = None,
) -> EpisodeStats:
    """One block's episodes under `policy`, at the image size the policy was trained with."""
    image_size = tuple(cfg.image_size or policy.image_size or DEFAULT_IMAGE_SIZE)
    return run_batch(
        env, policy, seed, combo.instruction, cfg.ensemble, image_size, cfg.action_convention, on_step
    )


def evaluate_block(cfg: EvalCfg, policy: EvalPolicy, combo: Combination, block: int) -> list[dict]:
    size = cfg.batch_size
    env, seed = block_env(cfg, combo, block)
    recorder = (
        HeadCameraRecorder(env, cfg.video_episodes - block * size)
        if cfg.video_episodes > block * size
        else None
    )
    stats = run_block(cfg, policy, combo, env, seed, recorder)
    if recorder is not None:
        recorder.write(
            run_dir(cfg) / "videos" / cfg.split_name / combo.name.replace("/", "_") / f"block_{block}"
        )
    returns = sum(stats.reward_terms.values())
    return [
        {
            "robot": combo.robot,
            "object_id": combo.object_id,
            "category": combo.category,
            "skill": combo.skill,
            "scene": combo.scene,
            "split": combo.split,
            "scene_split": combo.scene_split,
            "instruction": combo.instruction,
            "policy": policy.name,
            "episode": block * size + slot,
            "seed": seed,
            "slot": slot,
            "success": bool(stats.success[slot]),
            "length": int(stats.length[slot]),
            "return": float(returns[slot]),
            "nan_actions": int(stats.nan_actions[slot]),
        }
        for slot in range(size)
    ]


# What decides an episode's outcome; a run's protocol (subset, split), videos and batching may change between
# reruns of the same name, which then run only the missing episodes.
RESULT_SETTINGS = (
    "robot",
    "policy.kind",
    "policy.checkpoint",
    "policy.runs_dir",
    "policy.rename",
    "episodes_per_batch",
    "seed",
    "ensemble",
    "action_convention",
    "image_size",
    "env",
)


def check_same_settings(
    out: Path, settings: dict, task_checkpoints: dict[str, str], training: dict
) -> dict[str, str]:
    """A run directory that holds results keeps the settings they were made with, each task's looked-up
    checkpoint (a teacher trained on since is found anew) and the policy's weights (a model trained again
    under the same checkpoint path): a rerun otherwise would report the old episodes as its own. Returns the
    task checkpoints of the old episodes and the new."""
    saved = out / "config.json"
    if not saved.exists() or not any(p.stat().st_size for p in out.glob("*.jsonl")):
        return task_checkpoints
    config = read_json(saved)
    changes = changed_values(config["eval"], settings, RESULT_SETTINGS)
    before = config.get("task_checkpoints", {})
    changes += [
        f"{task}: {before[task]} -> {path}"
        for task, path in task_checkpoints.items()
        if before.get(task, path) != path
    ]
    # Results recorded before weights had digests cannot be told apart: they are taken as they are.
    weights_before = config.get("policy_training", {}).get("weights_sha256")
    weights_now = training.get("weights_sha256")
    if weights_before and weights_now and weights_before != weights_now:
        changes.append(f"policy weights sha256 {weights_before[:12]}... -> {weights_now[:12]}...")
    if changes:
        raise ConfigMismatchError(
            f"{out} holds results made with other settings ({'; '.join(changes)}); "
            "choose another name=... or delete that directory to start over"
        )
    return {**before, **task_checkpoints}


Block = tuple[int, Combination, int]  # (combination index, combination, block index)


def worker_policy(cfg: PolicyCfg) -> EvalPolicy:
    """A worker process's policy, built once its video libraries are as quiet as the command's."""
    quiet_video_libraries()
    return build_policy(cfg)


def evaluate_item(cfg: EvalCfg, policy: EvalPolicy, item: Block) -> list[dict]:
    """A block's records, here or in a worker that built its own policy from the config (`cfg.workers`)."""
    _, combo, block = item
    return evaluate_block(cfg, policy, combo, block)


def evaluate(cfg: EvalCfg, policy: EvalPolicy | None = None) -> dict:
    """Run every missing episode of the selected protocol; returns the summary of the results file."""
    size = cfg.batch_size
    if cfg.subset.episodes % size:
        raise InputError(
            f"subset.episodes ({cfg.subset.episodes}) must be a multiple of episodes_per_batch "
            f"({size}) so that every episode keeps its seed"
        )
    combos = select_combinations(cfg.robot, cfg.subset)
    out = check_writable(run_dir(cfg), "output_dir")
    settings = OmegaConf.to_container(OmegaConf.structured(cfg))
    if policy is not None and cfg.workers > 1:
        raise InputError(
            f"workers={cfg.workers}: each worker builds its policy from the policy config; "
            "a policy object passed to evaluate() runs in this process (workers=1)"
        )
    policy = policy or build_policy(cfg.policy)
    expected = get_robot(cfg.robot).action_dim
    if policy.action_dim not in (None, expected):
        raise InputError(
            f"{policy.name} predicts {policy.action_dim}-d actions but robot={cfg.robot} takes "
            f"{expected}-d ones; evaluate it with the robot it was trained for"
        )
    check_action_index(cfg.ensemble.action_index, policy.chunk_length)
    tasks = {(c.robot, c.object_id, c.skill) for c in combos}
    checkpoints = check_same_settings(out, settings, policy.check_tasks(tasks), policy.training or {})
    with ResultsFile(out / f"{cfg.split_name}.jsonl") as results:
        config = {
            "eval": settings,
            "policy_inputs": sorted(policy.inputs),
            "policy_training": policy.training or {},
            "task_checkpoints": checkpoints,
        }
        write_json_atomic(out / "config.json", config)
        complete = run_missing_episodes(cfg, policy, combos, results)
        summary = summarize(read_records(results.path))
        if complete:  # last, so that a stopped run never looks finished (results.finished)
            write_json_atomic(summary_path(results.path), summary)
    return summary


def run_missing_episodes(
    cfg: EvalCfg, policy: EvalPolicy, combos: list[Combination], results: ResultsFile
) -> bool:
    """Every block of the protocol whose episodes the results file lacks, appended as each finishes, until
    `piece_minutes` have passed; returns whether every block is in."""
    size = cfg.batch_size
    todo = [
        (k, combo, block)
        for k, combo in enumerate(combos)
        for block in range(cfg.subset.episodes // size)
        if not {
            (combo.robot, combo.object_id, combo.skill, combo.scene, block * size + s) for s in range(size)
        }
        <= results.done
    ]
    total = len(combos) * cfg.subset.episodes
    # Up front, since the paper protocol on a CPU runs for hours: what there is to do and what a rerun skips.
    print(
        f"{policy.name} on {cfg.split_name}: {len(combos)} combinations x {cfg.subset.episodes} episodes = "
        f"{total} episodes; {total - len(todo) * size} done, {len(todo) * size} to run in batches of {size}",
        flush=True,
    )
    progress = Progress(len(todo) * size, "episodes")
    finished = run_in_pool(
        partial(evaluate_item, cfg), todo, cfg.workers, partial(worker_policy, cfg.policy), local_state=policy
    )
    deadline = time.monotonic() + 60 * cfg.piece_minutes if cfg.piece_minutes > 0 else float("inf")
    for n, ((k, combo, block), records) in enumerate(finished, start=1):
        results.append(records)
        rate = sum(r["success"] for r in records) / len(records)
        print(
            f"[{k + 1}/{len(combos)}] {combo.name} block {block}: success {rate:.2f} | "
            f"{progress.advance(size)}",
            flush=True,
        )
        if time.monotonic() > deadline and n < len(todo):
            finished.close()  # stops the workers; their unfinished blocks are run by the next call
            print(f"piece_minutes reached with {len(todo) - n} blocks left: a rerun resumes", flush=True)
            return False
    return True


@hydra.main(config_path="../../conf", config_name="eval", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    quiet_video_libraries()
    print(json.dumps(evaluate(to_dataclass(with_env_task(cfg), EvalCfg).check())["overall"], indent=2))


if __name__ == "__main__":
    main()

"""Evaluate a PPO teacher checkpoint: success over N seeded episodes, reward breakdown,
optional head-camera MP4s.

    python -m mobilemani_rl.rl.eval checkpoint=outputs/rl/g1/test/box/open/model_1499.pt [episodes=256]
        [seed=1000] [video_episodes=2]

The task, env and PPO settings come from the run's saved config.yaml; each object's episodes run as one batch
with the deterministic policy. A multi-object (category) policy is evaluated on the category's train and test
objects; its `success_rate` is the mean over the objects it trained on (`trained` in each object's entry), the
others show how it generalises (`success_by_split`). Results are written next to the checkpoint as
eval_<checkpoint>_<seed>.json.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # this command renders offscreen; mujoco reads it when imported

import dataclasses
import json
from pathlib import Path

import hydra
import numpy as np
from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.assets.objects import CATEGORIES, SPLITS, catalog_ids, get_object
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.rollout import run_first_episodes
from mobilemani_rl.envs.video import HeadCameraRecorder
from mobilemani_rl.rl.config import EvalRlCfg, RLCfg
from mobilemani_rl.rl.factory import policy_objects
from mobilemani_rl.rl.teacher import TeacherPolicy, check_checkpoint_file, load_teacher, run_config
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.io import write_json_atomic
from mobilemani_rl.utils.progress import Progress


def evaluation_objects(task_object: str) -> dict[str, list[str]]:
    """Objects to evaluate by split: the run's object, or a category's train and test objects."""
    if task_object in CATEGORIES:
        return {split: catalog_ids(task_object, split) for split in SPLITS}
    return {get_object(task_object).split or "train": [task_object]}


def evaluate(checkpoint: Path, episodes: int, seed: int, video_episodes: int = 0) -> dict:
    """Success and reward breakdown of a checkpoint over `episodes` seeded episodes per evaluated object."""
    check_checkpoint_file(checkpoint)
    run_cfg = run_config(checkpoint)
    run = to_dataclass(run_cfg, RLCfg)
    env_cfg = run.env_cfg()
    env_cfg.num_envs = episodes
    trained = set(policy_objects(env_cfg.task.object, run.objects_per_policy) or [env_cfg.task.object])
    todo = [
        (split, object_id)
        for split, ids in evaluation_objects(env_cfg.task.object).items()
        for object_id in ids
    ]
    progress = Progress(len(todo), "objects")  # a category is ~40 objects of `episodes` episodes each
    per_object: dict[str, dict] = {}
    actor = None
    for split, object_id in todo:
        env = MobileManiEnv(
            dataclasses.replace(env_cfg, task=dataclasses.replace(env_cfg.task, object=object_id))
        )
        if actor is None:
            _, actor = load_teacher(checkpoint, env=env, cfg=run_cfg)
        recorder = HeadCameraRecorder(env, video_episodes) if video_episodes else None
        stats = run_first_episodes(env, TeacherPolicy(env, actor), seed=seed, on_step=recorder)
        per_object[object_id] = {"split": split, "trained": object_id in trained, **stats.summary()}
        if recorder is not None:
            per_object[object_id]["videos"] = recorder.write(
                checkpoint.parent / f"eval_videos_{checkpoint.stem}" / object_id.replace("/", "_")
            )
        print(
            f"{object_id} ({split}{', trained' if object_id in trained else ''}): success "
            f"{per_object[object_id]['success_rate']:.3f} | {progress.advance()}",
            flush=True,
        )
    by_split = {
        split: float(np.mean([r["success_rate"] for r in per_object.values() if r["split"] == split]))
        for split in {r["split"] for r in per_object.values()}
    }
    result = {
        "checkpoint": str(checkpoint),
        "seed": seed,
        "task": OmegaConf.to_container(run_cfg.task),
        "episodes_per_object": episodes,
        "success_rate": float(np.mean([r["success_rate"] for r in per_object.values() if r["trained"]])),
        "success_by_split": by_split,
        "objects": per_object,
    }
    write_json_atomic(checkpoint.parent / f"eval_{checkpoint.stem}_{seed}.json", result)
    return result


@hydra.main(config_path="../../conf", config_name="eval_rl", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    run = to_dataclass(cfg, EvalRlCfg).check()
    result = evaluate(Path(run.checkpoint), run.episodes, run.seed, run.video_episodes)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()

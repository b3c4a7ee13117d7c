"""Evaluate a PPO teacher checkpoint: success over N seeded episodes, reward breakdown, optional head-camera MP4s.

    python -m mobilemani_rl.eval checkpoint=runs/rl/g1/test/box/open/model_1499.pt [episodes=256] [seed=1000]
        [video_episodes=2]

The task, env and PPO settings come from the run's saved config.yaml; each object's episodes run as one batch
with the deterministic policy. A multi-object (category) policy is evaluated on the category's train and test
objects. Results are written next to the checkpoint as eval_<checkpoint>_<seed>.json.
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path

import cv2
import hydra
import mujoco
import numpy as np
from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.assets.objects import CATEGORIES, SPLITS, catalog_ids, get_object
from mobilemani_rl.envs.config import env_cfg_from_hydra
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.rl.run_dir import write_json_atomic
from mobilemani_rl.rollout import run_first_episodes
from mobilemani_rl.teacher import TeacherPolicy, load_teacher, run_config

VIDEO_SIZE = 320


class HeadCameraRecorder:
    """Collects head-camera frames of the first k envs while their first episode runs."""

    def __init__(self, env: MobileManiEnv, episodes: int) -> None:
        self.env, self.ids = env, list(range(min(episodes, env.num_envs)))
        self.renderer = mujoco.Renderer(env.model, VIDEO_SIZE, VIDEO_SIZE)
        self.frames: dict[int, list[np.ndarray]] = {i: [] for i in self.ids}
        self.finished: set[int] = set()

    def __call__(self, result) -> None:
        for i in self.ids:
            if i in self.finished:
                continue
            self.renderer.update_scene(self.env.batch.get_data(i), camera=self.env.robot.head_camera)
            self.frames[i].append(self.renderer.render())
            if i in result.done_ids:
                self.finished.add(i)

    def write(self, directory: Path) -> list[str]:
        directory.mkdir(parents=True, exist_ok=True)
        paths = []
        for i, frames in self.frames.items():
            path = directory / f"episode_{i:03d}.mp4"
            tmp = path.with_name(path.stem + ".tmp.mp4")
            writer = cv2.VideoWriter(str(tmp), cv2.VideoWriter_fourcc(*"mp4v"), 30, (VIDEO_SIZE, VIDEO_SIZE))
            for frame in frames:
                writer.write(cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
            writer.release()
            os.replace(tmp, path)
            paths.append(str(path))
        return paths


def evaluation_objects(task_object: str) -> dict[str, list[str]]:
    """Objects to evaluate by split: the run's object, or a category's train and test objects."""
    if task_object in CATEGORIES:
        return {split: catalog_ids(task_object, split) for split in SPLITS}
    return {get_object(task_object).split or "train": [task_object]}


def evaluate(checkpoint: Path, episodes: int, seed: int, video_episodes: int = 0) -> dict:
    """Success and reward breakdown of a checkpoint over `episodes` seeded episodes per evaluated object."""
    if not checkpoint.is_file():
        raise FileNotFoundError(f"checkpoint {checkpoint} does not exist")
    run_cfg = run_config(checkpoint)
    env_cfg = env_cfg_from_hydra(run_cfg)
    env_cfg.num_envs = episodes
    per_object: dict[str, dict] = {}
    actor = None
    for split, object_ids in evaluation_objects(env_cfg.task.object).items():
        for object_id in object_ids:
            env = MobileManiEnv(dataclasses.replace(env_cfg, task=dataclasses.replace(env_cfg.task,
                                                                                      object=object_id)))
            if actor is None:
                _, actor = load_teacher(checkpoint, env=env, cfg=run_cfg)
            recorder = HeadCameraRecorder(env, video_episodes) if video_episodes else None
            stats = run_first_episodes(env, TeacherPolicy(env, actor), seed=seed, on_step=recorder)
            per_object[object_id] = {"split": split, **stats.summary()}
            if recorder is not None:
                per_object[object_id]["videos"] = recorder.write(
                    checkpoint.parent / f"eval_videos_{checkpoint.stem}" / object_id.replace("/", "_"))
    by_split = {split: float(np.mean([r["success_rate"] for r in per_object.values() if r["split"] == split]))
                for split in {r["split"] for r in per_object.values()}}
    result = {"checkpoint": str(checkpoint), "seed": seed, "task": OmegaConf.to_container(run_cfg.task),
              "episodes_per_object": episodes, "success_rate": float(np.mean([r["success_rate"]
                                                                               for r in per_object.values()])),
              "success_by_split": by_split, "objects": per_object}
    write_json_atomic(checkpoint.parent / f"eval_{checkpoint.stem}_{seed}.json", result)
    return result


@hydra.main(config_path="../conf", config_name="eval_rl", version_base="1.3")
def main(cfg: DictConfig) -> None:
    if cfg.checkpoint is None:
        raise SystemExit("checkpoint=<path to a model_*.pt> is required")
    result = evaluate(Path(cfg.checkpoint), cfg.episodes, cfg.seed, cfg.video_episodes)
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()

"""Head-camera MP4s of evaluation episodes (teacher evaluation and the closed-loop harness)."""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import mujoco
import numpy as np

from mobilemani_rl.envs.mobilemani_env import MobileManiEnv

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

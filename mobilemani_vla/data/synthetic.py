"""A small synthetic MobileManiDataset in the exporter's schema, for tests, benchmarks and smoke runs of the
VLA before real data exists. Each frame's images, wrist pose and action chunk are smooth functions of the
frame's phase in its episode, so a model can fit them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from lerobot.datasets.lerobot_dataset import LeRobotDataset

from mobilemani_data import schema
from mobilemani_data.frame import rotation_6d
from mobilemani_rl.utils.rotations import quat_from_euler
from mobilemani_vla.config import ROBOT_ACTION_DIMS

TASKS = ("open box", "pick cracker box", "open washing_machine")


def _image(phase: float, channel: int, height: int, width: int) -> np.ndarray:
    """A bright square that moves with the phase on a dark, channel-tinted background."""
    img = np.full((height, width, 3), 30, np.uint8)
    img[..., channel % 3] = 80
    size = max(2, min(height, width) // 4)
    y = int(phase * (height - size))
    x = int((1.0 - phase) * (width - size))
    img[y : y + size, x : x + size] = 230
    return img


def write_synthetic_dataset(
    root: Path,
    robot: str = "g1",
    episodes: int = 1,
    length: int = 30,
    height: int = 48,
    width: int = 64,
    seed: int = 0,
) -> Path:
    action_dim = ROBOT_ACTION_DIMS[robot]
    hand = action_dim - 6
    rng = np.random.default_rng(seed)
    ds = LeRobotDataset.create(
        repo_id=f"synthetic/{robot}",
        fps=schema.FPS,
        root=root,
        use_videos=True,
        features=schema.features(action_dim, hand, height, width),
    )
    for episode in range(episodes):
        offset = rng.uniform(-1.0, 1.0, size=3).astype(np.float32)
        for i in range(length):
            phase = i / max(1, length - 1)
            wave = np.sin(2 * np.pi * (phase + np.arange(action_dim) / action_dim)).astype(np.float32)
            frame = {
                schema.image_key(c, m): _image(phase, k, height, width)
                for k, (c, m) in enumerate((c, m) for c in schema.CAMERAS for m in schema.MODALITIES)
            }
            frame.update(
                {
                    schema.STATE: np.concatenate(
                        [
                            [0.4 + 0.2 * phase, 0.1, 0.8 - 0.1 * phase],
                            rotation_6d(quat_from_euler(np.array([0.0, phase, 0.0]))),
                            np.zeros(hand),
                        ]
                    ).astype(np.float32),
                    schema.ACTION: wave,
                    schema.WORLD_STATE: np.concatenate([np.full(12, phase), np.zeros(hand)]).astype(
                        np.float32
                    ),
                    schema.WORLD_ACTION: wave,
                    schema.GRASP_POINT_BASE: offset,
                    schema.GOAL_POINT_BASE: offset + np.float32(0.1),
                    "task": TASKS[episode % len(TASKS)],
                }
            )
            ds.add_frame(frame)
        ds.save_episode()
    ds.finalize()
    return root

"""Reads the MobileManiDataset (LeRobot v3) for the VLA: selected cameras, base-frame states, 16-step chunks."""

from __future__ import annotations

from pathlib import Path

from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata
from lerobot.datasets.lerobot_dataset import LeRobotDataset

from mobilemani_data import schema
from mobilemani_vla.config import VLACfg
from mobilemani_vla.processor import STATE_KEYS, camera_key


def required_features(cfg: VLACfg) -> list[str]:
    return ([camera_key(c) for c in cfg.inputs.cameras] + [STATE_KEYS[s] for s in cfg.inputs.states]
            + [schema.ACTION_BASE])


def open_dataset(cfg: VLACfg) -> LeRobotDataset:
    """The local dataset with `action_base` chunks of `diffusion.chunk` steps (LeRobot marks rows past the episode
    end in `action_base_is_pad`); stops with one message if the dataset does not fit the config."""
    root = Path(cfg.data.root)
    if not (root / "meta" / "info.json").is_file():
        raise FileNotFoundError(f"no LeRobot dataset at {root} (set data.root; export one with mobilemani_data)")
    meta = LeRobotDatasetMetadata(cfg.data.repo_id, root=root)
    missing = [k for k in required_features(cfg) if k not in meta.features]
    if missing:
        raise KeyError(f"dataset {root} lacks features {missing} needed by inputs {cfg.inputs}")
    action_shape = tuple(meta.features[schema.ACTION_BASE]["shape"])
    if action_shape != (cfg.action_dim,):
        raise ValueError(f"dataset actions have shape {action_shape} but robot={cfg.robot} needs ({cfg.action_dim},)")
    deltas = {schema.ACTION_BASE: [i / meta.fps for i in range(cfg.diffusion.chunk)]}
    return LeRobotDataset(cfg.data.repo_id, root=root, episodes=cfg.data.episodes, delta_timestamps=deltas,
                          video_backend=cfg.data.video_backend)


def dataset_tasks(dataset: LeRobotDataset) -> list[str]:
    return sorted(dataset.meta.tasks.index)

"""Reads the MobileManiDataset (LeRobot v3) for the VLA: selected cameras, base-frame states, 16-step chunks.

Every frame's vectors are read once into memory (`FrameTable`); images come either from the decoded-frame
cache (`frame_cache`, the default: training is then compute-bound) or, with `data.cache=false`, from LeRobot's
own video decoding per sample. Both give the same frame dicts to the processor. A few whole episodes are held
out of training (`data.heldout_episodes`) for the diagnostics;
normalisation bounds come from the training episodes only. A frame whose vectors hold a NaN or an infinity
stops training before it starts, naming its parquet file, episode, key and frame: it would be a label, and
it would make the normalisation bounds NaN.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata
from lerobot.datasets.lerobot_dataset import LeRobotDataset
from torch.utils.data import Dataset

from mobilemani_data import schema
from mobilemani_data.metadata import open_dataset_metadata
from mobilemani_rl.utils.errors import InputError, MissingFileError
from mobilemani_rl.utils.io import non_finite
from mobilemani_vla.config import VLACfg
from mobilemani_vla.data.frame_cache import cached_images
from mobilemani_vla.model.normalizer import Normalizer
from mobilemani_vla.model.processor import camera_key, state_features

PAD = f"{schema.ACTION}_is_pad"


def vector_keys(states: list[str]) -> list[str]:
    """The normalised vectors a model reads: its action chunk and its state inputs."""
    return [schema.ACTION] + state_features(states)


def required_features(cfg: VLACfg) -> list[str]:
    return [camera_key(c) for c in cfg.inputs.cameras] + vector_keys(cfg.read_states)


def open_metadata(cfg: VLACfg) -> LeRobotDatasetMetadata:
    """The dataset's metadata; stops with one message if there is no dataset or it does not fit the config."""
    root = Path(cfg.data.root)
    if not (root / "meta").is_dir():
        raise MissingFileError(
            f"no LeRobot dataset at {root} (set data.root; export one with mobilemani_data)"
        )
    meta = open_dataset_metadata(cfg.data.repo_id, root)
    missing = [k for k in required_features(cfg) if k not in meta.features]
    if missing:
        raise InputError(f"dataset {root} lacks features {missing} needed by inputs {cfg.inputs}")
    have = tuple(meta.features[schema.ACTION]["shape"])
    if have != (cfg.action_dim,):
        raise InputError(f"dataset actions have shape {have} but robot={cfg.robot} needs ({cfg.action_dim},)")
    return meta


@dataclass
class FrameTable:
    """Every frame's vectors in dataset index order, plus where each frame's episode ends."""

    columns: dict[str, np.ndarray]
    episode_index: np.ndarray  # (frames,)
    episode_end: np.ndarray  # (frames,) dataset index one past the last frame of the row's episode
    tasks: list[str]  # (frames,) instruction of each row

    @classmethod
    def read(cls, meta: LeRobotDatasetMetadata, keys: list[str]) -> FrameTable:
        table = LeRobotDataset(meta.repo_id, root=meta.root).hf_dataset.with_format("numpy")[:]
        episode_index = table["episode_index"]
        ends = {ep["episode_index"]: ep["dataset_to_index"] for ep in meta.episodes}
        names = {int(i): task for task, i in zip(meta.tasks.index, meta.tasks["task_index"], strict=True)}
        columns = {k: table[k] for k in keys}
        if bad := non_finite(columns):
            key, row, value = bad[0]
            episode = int(episode_index[row])
            raise InputError(
                f"{Path(meta.root) / meta.get_data_file_path(episode)}: episode {episode} {key} frame "
                f"{int(table['frame_index'][row])} is not finite ({value}); training refuses non-finite "
                "frames (python -m mobilemani_data.validate lists them all)"
            )
        return cls(
            columns,
            episode_index,
            np.array([ends[e] for e in episode_index]),
            [names[int(i)] for i in table["task_index"]],
        )

    def rows(self, episodes: np.ndarray) -> np.ndarray:
        return np.flatnonzero(np.isin(self.episode_index, episodes))

    def digest(self) -> str:
        """sha256 of every frame's episode and action label: two datasets share it only if they hold the same
        demonstrations (a dataset rebuilt from other teachers differs), whatever their paths."""
        digest = hashlib.sha256(np.ascontiguousarray(self.episode_index, dtype=np.int64).tobytes())
        digest.update(np.ascontiguousarray(self.columns[schema.ACTION], dtype=np.float64).tobytes())
        return digest.hexdigest()

    def chunk(self, row: int, length: int) -> tuple[np.ndarray, np.ndarray]:
        """Dataset rows of the chunk starting at `row` (the episode's last frame repeated past its end) and
        the padding mask, as LeRobot's delta timestamps give them."""
        wanted = row + np.arange(length)
        return np.minimum(wanted, self.episode_end[row] - 1), wanted >= self.episode_end[row]


def dataset_digest(repo_id: str, root: str | Path) -> str:
    """FrameTable.digest of a local dataset: its episodes and action labels."""
    return FrameTable.read(open_dataset_metadata(repo_id, root), [schema.ACTION]).digest()


def chosen_episodes(episodes: list[int] | None, total: int, root: str) -> list[int]:
    """`data.episodes`, or every episode when unset; each must be one of the dataset's, once."""
    if episodes is None:
        return list(range(total))
    unknown = sorted({e for e in episodes if not 0 <= e < total})
    if unknown or not episodes or len(set(episodes)) != len(episodes):
        raise InputError(
            f"data.episodes={list(episodes)}: name one or more of the {total} episodes of {root} "
            f"(0 to {total - 1}), without repeats" + (f"; not among them: {unknown}" if unknown else "")
        )
    return list(episodes)


def split_episodes(episodes: list[int], heldout: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(training, held-out) episode indices; the held-out ones are a seeded random choice."""
    episodes = np.asarray(sorted(episodes))
    if heldout >= len(episodes):
        raise InputError(f"data.heldout_episodes={heldout} leaves no training episode of {len(episodes)}")
    chosen = np.random.default_rng(seed).choice(len(episodes), size=heldout, replace=False)
    mask = np.zeros(len(episodes), bool)
    mask[chosen] = True
    return episodes[~mask], episodes[mask]


def fit_normalizer(table: FrameTable, rows: np.ndarray, states: list[str]) -> Normalizer:
    """Bounds from the frames `rows`; finite ones, as FrameTable.read refuses non-finite frames."""
    values = {k: table.columns[k][rows] for k in vector_keys(states)}
    if bad := non_finite(values):  # a table built around FrameTable.read's check
        key, row, value = bad[0]
        raise InputError(f"normalisation statistics: {key} of frame {int(rows[row])} is not finite ({value})")
    return Normalizer.fit(values)


class CachedFrames(Dataset):
    """Frames `rows` of the dataset: images from the decoded-frame cache,
    vectors and chunks from the table."""

    def __init__(
        self,
        table: FrameTable,
        rows: np.ndarray,
        images: dict[str, np.ndarray],
        cameras: list[str],
        states: list[str],
        chunk: int,
    ) -> None:
        self.table, self.rows, self.images = table, rows, images
        self.cameras, self.states, self.chunk_length = cameras, states, chunk

    def __len__(self) -> int:
        return len(self.rows)

    def __getitem__(self, i: int) -> dict:
        row = int(self.rows[i])
        chunk_rows, pad = self.table.chunk(row, self.chunk_length)
        # copies: the cache is a read-only map
        item = {camera_key(c): torch.from_numpy(np.array(self.images[c][row])) for c in self.cameras}
        item.update({k: torch.from_numpy(self.table.columns[k][row]) for k in state_features(self.states)})
        item[schema.ACTION] = torch.from_numpy(self.table.columns[schema.ACTION][chunk_rows])
        item[PAD] = torch.from_numpy(pad)
        item["task"] = self.table.tasks[row]
        return item


@dataclass
class VLAData:
    meta: LeRobotDatasetMetadata
    table: FrameTable
    train_episodes: np.ndarray
    heldout_episodes: np.ndarray
    train: Dataset  # training frames, as frame dicts
    heldout: Dataset | None  # held-out frames, same format (None without held-out episodes)

    @property
    def tasks(self) -> list[str]:
        return sorted(self.meta.tasks.index)

    @property
    def image_size(self) -> list[int]:
        """(height, width) the dataset's images were rendered at."""
        return list(self.meta.features[self.meta.video_keys[0]]["shape"][:2])


def _decoded_frames(cfg: VLACfg, fps: int, episodes: np.ndarray) -> LeRobotDataset:
    deltas = {schema.ACTION: [i / fps for i in range(cfg.diffusion.chunk)]}
    return LeRobotDataset(
        cfg.data.repo_id,
        root=cfg.data.root,
        episodes=episodes.tolist(),
        delta_timestamps=deltas,
        video_backend=cfg.data.video_backend,
    )


def open_data(cfg: VLACfg, image_size: int, progress: bool = True) -> VLAData:
    """The training and held-out frames of the configured dataset (episodes `data.episodes`, or all)."""
    meta = open_metadata(cfg)
    episodes = chosen_episodes(cfg.data.episodes, meta.total_episodes, cfg.data.root)
    train_eps, heldout_eps = split_episodes(episodes, cfg.data.heldout_episodes, cfg.train.seed)
    table = FrameTable.read(meta, vector_keys(cfg.read_states))
    if cfg.data.cache:
        images = cached_images(
            Path(cfg.data.root), meta, cfg.inputs.cameras, image_size, cfg.data.video_backend, progress
        )

        def frames(eps: np.ndarray) -> Dataset:
            return CachedFrames(
                table, table.rows(eps), images, cfg.inputs.cameras, cfg.read_states, cfg.diffusion.chunk
            )
    else:

        def frames(eps: np.ndarray) -> Dataset:
            return _decoded_frames(cfg, meta.fps, eps)

    heldout = frames(heldout_eps) if len(heldout_eps) else None
    return VLAData(meta, table, train_eps, heldout_eps, frames(train_eps), heldout)

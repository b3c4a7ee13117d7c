"""LeRobot's dataset reader served from the frame cache (`mobilemani_vla.data.frame_cache`) instead of
decoding.

`lerobot-train` decodes every camera stream of every sample it draws: on the recipe's dataset (4 streams,
64 px) that is ~1.1-1.3 s of data loading per step of 16 on 2 cores (LeRobot's `data_s`), against 0.07-0.10 s
from the cache. Inside `served_from_frame_cache()`, `DatasetReader._query_videos` (LeRobot 0.6) returns the
frames from the same uint8 cache MobileManiVLA trains from, at the dataset's own image size (no resize): the
values LeRobot's decoder returns, read from a memory map. The cache is built on first use, or rebuilt when the
dataset's videos changed. Streams stored as LeRobot depth features (none in our datasets) are still decoded.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import torch
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata
from lerobot.datasets.dataset_reader import DatasetReader

from mobilemani_data import schema
from mobilemani_vla.data.frame_cache import cached_images
from mobilemani_vla.model.processor import camera_key

# feature name -> the frame cache's camera name ("observation.images.head_rgb" -> "head_rgb")
CACHE_CAMERAS = {camera_key(f"{c}_{m}"): f"{c}_{m}" for c in schema.CAMERAS for m in schema.MODALITIES}


class CachedStreams:
    """The video streams of one dataset that the frame cache holds: all of them when they are square frames of
    one size (as every export writes), none otherwise (then LeRobot decodes them)."""

    def __init__(self, root: Path, meta: LeRobotDatasetMetadata) -> None:
        streams = [key for key in meta.video_keys if key not in meta.depth_keys]
        shapes = sorted({tuple(meta.features[key]["shape"][:2]) for key in streams})
        self.keys: list[str] = []
        self.fps = meta.fps
        if len(shapes) != 1 or shapes[0][0] != shapes[0][1]:
            print(
                f"{root}: frames decoded per sample (the frame cache holds square frames of one size; "
                f"these streams are {shapes})",
                flush=True,
            )
            return
        self.keys = streams
        self.images = cached_images(root, meta, [CACHE_CAMERAS[key] for key in streams], shapes[0][0])

    def frames(self, key: str, episode: dict, timestamps: list[float], as_uint8: bool) -> torch.Tensor:
        """(len(timestamps), 3, H, W) frames of stream `key` at episode-relative `timestamps`, squeezed like
        LeRobot's reader when there is one."""
        offsets = np.clip(np.rint(np.asarray(timestamps) * self.fps).astype(int), 0, episode["length"] - 1)
        rows = episode["dataset_from_index"] + offsets
        frames = torch.from_numpy(np.ascontiguousarray(self.images[CACHE_CAMERAS[key]][rows]))
        return (frames if as_uint8 else frames.float() / 255.0).squeeze(0)


@contextmanager
def served_from_frame_cache() -> Iterator[None]:
    """Within the block, every LeRobot dataset reads its RGB video frames from its frame cache."""
    decode = DatasetReader._query_videos
    streams: dict[Path, CachedStreams] = {}

    def query_videos(reader: DatasetReader, query_timestamps: dict[str, list[float]], ep_idx: int) -> dict:
        root = Path(reader.root).resolve()
        if root not in streams:
            streams[root] = CachedStreams(root, reader._meta)
        cached = streams[root]
        episode = reader._meta.episodes[ep_idx]
        out = decode(reader, {k: v for k, v in query_timestamps.items() if k not in cached.keys}, ep_idx)
        for key, timestamps in query_timestamps.items():
            if key in cached.keys:
                out[key] = cached.frames(key, episode, timestamps, reader._return_uint8)
        return out

    DatasetReader._query_videos = query_videos
    try:
        yield
    finally:
        DatasetReader._query_videos = decode

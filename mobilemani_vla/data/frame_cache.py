"""Decoded camera frames of a LeRobot dataset, cached next to it so that VLA training is compute-bound.

Decoding four video streams costs ~20 ms per randomly accessed sample; the cache decodes every episode once,
sequentially, resizes the frames to the model's input size and keeps each camera stream as one uint8
array `<dataset>/vla_cache/<camera>_<size>px/images.npy` of shape (frames, 3, size, size), read through a
memory map. One array per camera, not per camera set: runs that read different cameras of one dataset (the
image-input ablation) share the streams they have in common, on a large dataset tens of GB of disk and of
decoding.
A manifest records a fingerprint of the files the frames come from (videos, episode metadata); a stream whose
fingerprint no longer matches is rebuilt. Each stream is built under a temporary name and renamed when
complete, so an interrupted build is never used; runs started together on one dataset build different streams
side by side, each stream once, and read the others' streams when they are done.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import math
import mmap
import shutil
from pathlib import Path

import numpy as np
import torch
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata
from lerobot.datasets.video_utils import decode_video_frames
from tqdm import tqdm

from mobilemani_data.metadata import VIDEO_DECODE_ERRORS
from mobilemani_rl.utils.errors import InputError, first_sentence
from mobilemani_rl.utils.io import read_json
from mobilemani_vla.model.processor import camera_key, resize_images

CACHE_DIR = "vla_cache"
MANIFEST = "manifest.json"
IMAGES = "images.npy"
TOLERANCE_S = 1e-4  # LeRobotDataset's default timestamp tolerance
FRAME_SOURCES = ("meta/info.json", "meta/episodes", "videos")  # what the cached frames are decoded from


def dataset_fingerprint(root: Path) -> str:
    """A digest of the files the cached frames come from (path, size, modification time): the videos and the
    metadata that places each episode in them. Reports written beside them (statistics, which `make data`
    rewrites on every run) change no frame."""
    digest = hashlib.sha256()
    for source in FRAME_SOURCES:
        top = root / source
        for path in sorted([top] if top.is_file() else (p for p in top.rglob("*") if p.is_file())):
            stat = path.stat()
            digest.update(f"{path.relative_to(root)}:{stat.st_size}:{stat.st_mtime_ns}\n".encode())
    return digest.hexdigest()


def cache_dir(root: Path, camera: str, size: int) -> Path:
    return root / CACHE_DIR / f"{camera}_{size}px"


def _decode_episode(
    root: Path, meta: LeRobotDatasetMetadata, episode: dict, camera: str, backend: str
) -> torch.Tensor:
    """All frames of one episode's camera stream, (length, 3, H, W) uint8."""
    key = camera_key(camera)
    start = episode[f"videos/{key}/from_timestamp"]
    timestamps = (start + np.arange(episode["length"]) / meta.fps).tolist()
    path = root / meta.get_video_file_path(episode["episode_index"], key)
    try:
        return decode_video_frames(path, timestamps, TOLERANCE_S, backend, return_uint8=True)
    except VIDEO_DECODE_ERRORS as err:
        raise InputError(
            f"episode {episode['episode_index']}'s {key} frames do not decode from {path} "
            f"({first_sentence(err)}); the video is damaged: export the dataset again"
        ) from err


def _build(
    root: Path,
    meta: LeRobotDatasetMetadata,
    camera: str,
    size: int,
    backend: str,
    target: Path,
    fingerprint: str,
    progress: bool,
) -> None:
    tmp = target.with_name(target.name + ".partial")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir(parents=True)
    images = np.lib.format.open_memmap(
        tmp / IMAGES, mode="w+", dtype=np.uint8, shape=(meta.total_frames, 3, size, size)
    )
    for episode in tqdm(
        meta.episodes, desc=f"frame cache {target.name}", unit="episode", disable=not progress
    ):
        rows = slice(episode["dataset_from_index"], episode["dataset_to_index"])
        frames = resize_images(_decode_episode(root, meta, episode, camera, backend).float() / 255.0, size)
        images[rows] = (frames * 255.0).round().clamp(0, 255).to(torch.uint8).numpy()
    images.flush()
    del images
    (tmp / MANIFEST).write_text(
        json.dumps(
            {"fingerprint": fingerprint, "camera": camera, "size": size, "frames": meta.total_frames},
            indent=1,
        )
    )
    shutil.rmtree(target, ignore_errors=True)
    tmp.rename(target)


def cached_images(
    root: Path,
    meta: LeRobotDatasetMetadata,
    cameras: list[str],
    size: int,
    backend: str = "pyav",
    progress: bool = True,
) -> dict[str, np.ndarray]:
    """Each camera's (frames, 3, size, size) uint8 frames in dataset index order; a stream is built on first
    use or when the dataset changed, otherwise read from disk."""
    fingerprint = dataset_fingerprint(root)
    ready: set[str] = set()
    # First the streams no other run is building, then a wait for the rest: runs started together build
    # different streams side by side.
    for wait in (False, True):
        for camera in cameras:
            if camera not in ready and _ensure_stream(
                root, meta, camera, size, backend, fingerprint, progress, wait
            ):
                ready.add(camera)
    return {camera: _random_access_map(cache_dir(root, camera, size) / IMAGES) for camera in cameras}


def _random_access_map(path: Path) -> np.ndarray:
    """The .npy array at `path`, read-only and memory-mapped for random access. Training reads single
    frames in random order; the kernel's default read-ahead fetches the pages around each one as well, which
    on a cache larger than the machine's memory reads many times the bytes asked for and evicts the pages
    other samples need (a batch of 32 frames of four streams: 0.27 s of reads with read-ahead, 0.04 s
    without)."""
    with path.open("rb") as f:
        version = np.lib.format.read_magic(f)
        header = (
            np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
        )
        shape, _, dtype = header(f)  # the cache is written C-ordered
        pages = mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_READ)  # stays valid once the file is closed
        offset = f.tell()
    if hasattr(pages, "madvise"):  # not on Windows
        pages.madvise(mmap.MADV_RANDOM)
    return np.frombuffer(pages, dtype=dtype, count=math.prod(shape), offset=offset).reshape(shape)


def _ensure_stream(
    root: Path,
    meta: LeRobotDatasetMetadata,
    camera: str,
    size: int,
    backend: str,
    fingerprint: str,
    progress: bool,
    wait: bool,
) -> bool:
    """Build one camera's stream unless it is up to date; False (nothing done) when another run holds it and
    `wait` is false."""
    target = cache_dir(root, camera, size)
    target.parent.mkdir(parents=True, exist_ok=True)
    manifest = target / MANIFEST
    with target.with_name(target.name + ".lock").open("a") as lock:  # released when the file closes
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            return False
        if not manifest.is_file() or read_json(manifest).get("fingerprint") != fingerprint:
            _build(root, meta, camera, size, backend, target, fingerprint, progress)
    return True

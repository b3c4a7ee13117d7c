"""Raw episode shards: one HDF5 file per (robot, object, skill, scene), written atomically.

Layout (FORMAT_VERSION 1). File attributes: the combination (robot, object_id, category, skill, scene, split,
scene_split), instruction, teacher, seed, fps, requested / collected episodes, attempts, steps, capped,
env_cfg (YAML of the EnvCfg the model and physics are rebuilt from) and `complete`, set last.
Group `episode_<k>` per kept episode, T control steps long, arrays with time first:

  state (T, nstate)    mjSTATE_INTEGRATION of every step's state, t = 0 (the reset) … T-1: replayable exactly
  action (T, A)        world-frame action applied from state t (clamped to [-1, 1]); it led to state t+1
  success (T,)         latched success flag at state t
  hand_pos/quat, base_pos/quat, palm_pos/quat, palm_linvel/angvel, grasp_pos/quat, grasp_linvel, joint_pos/vel
                       world-frame robot and object states at t
                       (the observation's quantities; joints: IK chain, hand)
  goal_pos (3,)        the episode's goal point

The state after the last action (the terminal step) is not stored: the env resets it in the same step, as the
reference drops its terminal frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

from mobilemani_rl.utils.io import replace_synced

FORMAT_VERSION = 1
SUFFIX = ".h5"
PARTIAL_SUFFIX = ".partial"
FRAME_KEYS = (
    "hand_pos",
    "hand_quat",
    "base_pos",
    "base_quat",
    "palm_pos",
    "palm_quat",
    "palm_linvel",
    "palm_angvel",
    "grasp_pos",
    "grasp_quat",
    "grasp_linvel",
    "joint_pos",
    "joint_vel",
)
TIME_KEYS = ("state", "action", "success") + FRAME_KEYS
HEADER_KEYS = (
    "format_version",
    "robot",
    "object_id",
    "category",
    "skill",
    "scene",
    "split",
    "scene_split",
    "instruction",
    "teacher",
    "seed",
    "fps",
    "requested",
    "collected",
    "attempts",
    "steps",
    "capped",
    "env_cfg",
    "complete",
)


class ShardError(RuntimeError):
    """A shard that cannot be read, is incomplete, or is inconsistent; the message names the file."""


@dataclass
class Episode:
    arrays: dict[str, np.ndarray]  # TIME_KEYS (T, ...) and goal_pos (3,)
    attrs: dict[str, int] = field(default_factory=dict)  # env_slot, start_step, length

    @property
    def length(self) -> int:
        return len(self.arrays["state"])


@dataclass
class Shard:
    path: Path
    header: dict
    episodes: list[Episode]


def write_shard(path: Path, header: dict, episodes: list[Episode], compression: int = 4) -> None:
    """Write to `<path>.partial`, then rename: a shard either exists complete or not at all."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + PARTIAL_SUFFIX)
    with h5py.File(tmp, "w") as f:
        f.attrs.update(
            {"format_version": FORMAT_VERSION, **header, "collected": len(episodes), "complete": False}
        )
        for k, ep in enumerate(episodes):
            group = f.create_group(f"episode_{k:03d}")
            group.attrs.update({**ep.attrs, "length": ep.length})
            for name, values in ep.arrays.items():
                # fletcher32 checksums make a flipped byte a read error instead of silently wrong data
                group.create_dataset(
                    name,
                    data=values,
                    compression="gzip",
                    compression_opts=compression,
                    shuffle=True,
                    fletcher32=True,
                )
        f.attrs["complete"] = True
    replace_synced(tmp, path, tmp)


def _attrs(f: h5py.File) -> dict:
    return {k: _plain(v) for k, v in f.attrs.items()}


def _read(path: Path) -> Shard:
    with h5py.File(path, "r") as f:
        header = _attrs(f)
        missing = [k for k in HEADER_KEYS if k not in header]
        if missing:
            raise ShardError(f"{path}: missing attributes {missing}")
        if header["format_version"] != FORMAT_VERSION:
            raise ShardError(f"{path}: format version {header['format_version']}, expected {FORMAT_VERSION}")
        if not header["complete"]:
            raise ShardError(f"{path}: not marked complete")
        names = sorted(k for k in f if k.startswith("episode_"))
        if len(names) != header["collected"]:
            raise ShardError(f"{path}: {len(names)} episodes stored, header says {header['collected']}")
        episodes = []
        for name in names:
            group = f[name]
            arrays = {k: group[k][()] for k in (*TIME_KEYS, "goal_pos")}
            lengths = {len(arrays[k]) for k in TIME_KEYS}
            if lengths != {group.attrs["length"]}:
                raise ShardError(f"{path}: {name} has inconsistent lengths {sorted(lengths)}")
            if not arrays["success"].any():
                raise ShardError(f"{path}: {name} never succeeds")
            episodes.append(Episode(arrays, {k: int(v) for k, v in group.attrs.items()}))
    return Shard(path, header, episodes)


def read_shard(path: Path) -> Shard:
    """Load a whole shard (a few MB) and check it; any failure is a ShardError naming the file."""
    try:
        return _read(path)
    except ShardError:
        raise
    except (
        OSError,
        KeyError,
        ValueError,
        TypeError,
    ) as err:  # h5py: truncated files, bad checksums, no such key
        raise ShardError(f"{path}: unreadable ({type(err).__name__}: {err})") from err


def complete_header(path: Path) -> dict | None:
    """The attributes (what it was collected with) of a readable shard marked complete, without its
    episodes; None for a missing, unreadable, unfinished or other-format file (collection redoes those)."""
    try:
        with h5py.File(path, "r") as f:
            header = _attrs(f)
    except OSError:
        return None
    complete = header.get("complete", False) and header.get("format_version") == FORMAT_VERSION
    return header if complete else None


def shard_paths(raw_dir: Path, robot: str) -> list[Path]:
    """Every shard of a robot, in a stable order (partial files are never listed)."""
    return sorted((raw_dir / robot).rglob(f"*{SUFFIX}"))


def _plain(value: object) -> object:
    """HDF5 attribute -> Python scalar."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, bytes):
        return value.decode()
    return value

"""Check raw shards and the exported LeRobot dataset:

    python -m mobilemani_data.validate robot=g1 [validate.replay_episodes=2]

Shards: readable, complete, consistent, and every float array of every episode finite (all episodes, one
vectorised pass per array; a problem names the shard, episode, key and first row). Replay: for a sample of
episodes, the world poses recomputed from each recorded state and the states reached by re-stepping the
physics equal the recorded ones within the tolerance. Shards are read one at a time, so a raw dataset larger
than memory validates.
Dataset: features as the schema says, one metadata line per episode, frame counts equal to the shards', every
float column of every parquet file finite (named by file, episode, key and frame), frames decodable. Prints
every problem (each naming its file) and exits non-zero if there is any.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path

import hydra
import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq
from lerobot.datasets.lerobot_dataset import LeRobotDataset
from omegaconf import DictConfig

from mobilemani_data import schema
from mobilemani_data.config import DataCfg, ValidateCfg
from mobilemani_data.convert import FIRST_FRAME
from mobilemani_data.metadata import (
    VIDEO_DECODE_ERRORS,
    open_dataset_metadata,
    read_episodes,
    read_export_report,
)
from mobilemani_data.replay import Replayer
from mobilemani_data.shards import Shard, ShardError, read_shard, shard_paths
from mobilemani_rl.assets.robots import get_robot
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.errors import first_sentence
from mobilemani_rl.utils.io import non_finite
from mobilemani_rl.utils.video_logs import quiet_video_libraries


@dataclass
class ShardChecks:
    """What validation keeps of the raw shards: it reads one at a time, so memory stays that of one shard."""

    # each readable shard's episode lengths, by its path relative to raw_dir
    lengths: dict[str, list[int]] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    replayed: int = 0
    worst: float = 0.0  # the largest replay error


def episode_non_finite(shard: Shard, k: int) -> list[str]:
    """A problem per float array of episode `k` of `shard` that holds a NaN or an infinity."""
    return [
        f"{shard.path}: episode {k} {key} row {row} is not finite ({value})"
        for key, row, value in non_finite(shard.episodes[k].arrays)
    ]


def check_shards(raw_dir: Path, robot: str, cfg: ValidateCfg) -> ShardChecks:
    """Every shard readable and every float array of every episode finite; the first episode of the first
    `cfg.replay_episodes` readable shards that hold one replayed."""
    checks = ShardChecks()
    for path in shard_paths(raw_dir, robot):
        try:
            shard = read_shard(path)
        except ShardError as err:
            checks.problems.append(str(err))
            continue
        checks.lengths[str(path.relative_to(raw_dir))] = [episode.length for episode in shard.episodes]
        checks.problems += [p for k in range(len(shard.episodes)) for p in episode_non_finite(shard, k)]
        if checks.replayed < cfg.replay_episodes and shard.episodes:
            errors = Replayer(shard).check(shard.episodes[0])
            checks.replayed += 1
            checks.worst = max(checks.worst, errors.worst())
            if errors.worst() > cfg.tolerance:
                checks.problems.append(
                    f"{shard.path}: episode 0 replays with error {errors} > {cfg.tolerance}"
                )
    return checks


def column_values(column: pa.ChunkedArray) -> np.ndarray:
    """A parquet column as a (rows, ...) array: a vector feature (a list per row) as (rows, size)."""
    column = column.combine_chunks()
    if pa.types.is_list(column.type) or pa.types.is_fixed_size_list(column.type):
        return pc.list_flatten(column).to_numpy(zero_copy_only=False).reshape(len(column), -1)
    return column.to_numpy(zero_copy_only=False)


def check_finite_dataset(root: Path, float_keys: list[str]) -> list[str]:
    """Every float column (`float_keys`) of every data file of the dataset holds finite numbers; a file at a
    time, so memory stays that of one file."""
    problems = []
    for path in sorted((root / "data").rglob("*.parquet")):
        table = pq.read_table(path, columns=[*float_keys, "episode_index", "frame_index"])
        values = {key: column_values(table[key]) for key in float_keys}
        for key, row, value in non_finite(values):
            episode, frame = table["episode_index"][row].as_py(), table["frame_index"][row].as_py()
            problems.append(f"{path}: episode {episode} {key} frame {frame} is not finite ({value})")
    return problems


def check_dataset(
    root: Path,
    repo_id: str,
    robot_name: str,
    shard_lengths: dict[str, list[int]],
    cfg: ValidateCfg,
) -> list[str]:
    robot = get_robot(robot_name)
    report = read_export_report(root)
    try:
        meta = open_dataset_metadata(repo_id, root)
    except FileNotFoundError as err:
        return [str(err)]
    problems = []
    expected = schema.features(
        robot.action_dim,
        len(robot.hand_joints),
        report["height"],
        report["width"],
        tuple(report["cameras"]),
        tuple(report["modalities"]),
    )
    for name, spec in expected.items():
        found = meta.features.get(name)
        if found is None or tuple(found["shape"]) != spec["shape"] or found["dtype"] != spec["dtype"]:
            problems.append(
                f"{root}: feature {name} is {found and (found['dtype'], found['shape'])}, "
                f"schema says {(spec['dtype'], spec['shape'])}"
            )
    episodes = read_episodes(root)
    if len(episodes) != meta.total_episodes:
        problems.append(f"{root}: {len(episodes)} metadata lines for {meta.total_episodes} episodes")
    lengths = dict(zip(meta.episodes["episode_index"], meta.episodes["length"], strict=True))
    for line in episodes:
        i = line["episode_index"]
        missing = [k for k in schema.EPISODE_METADATA if k not in line]
        shard = shard_lengths.get(line["shard"])
        if missing:
            problems.append(f"{root}: episode {i} lacks metadata {missing}")
        if lengths.get(i) != line["length"]:
            problems.append(
                f"{root}: episode {i} has {lengths.get(i)} frames, metadata says {line['length']}"
            )
        if shard is not None and shard[line["shard_episode"]] - FIRST_FRAME != line["length"]:
            problems.append(f"{root}: episode {i} length differs from its shard {line['shard']}")
    if meta.total_frames != sum(line["length"] for line in episodes):
        problems.append(f"{root}: {meta.total_frames} frames, metadata lengths sum to another count")
    problems += check_finite_dataset(
        root, [key for key, spec in meta.features.items() if spec["dtype"] in ("float32", "float64")]
    )
    ds = LeRobotDataset(meta.repo_id, root=root, video_backend="pyav")
    for index in np.linspace(0, len(ds) - 1, cfg.decode_frames).round().astype(int):
        try:
            frame = ds[int(index)]
        except VIDEO_DECODE_ERRORS as err:
            episode = int(ds.hf_dataset[int(index)]["episode_index"])
            videos = sorted({str(root / meta.get_video_file_path(episode, key)) for key in meta.video_keys})
            problems.append(
                f"{root}: frame {index} does not decode ({first_sentence(err)}); "
                f"the videos of its episode {episode}: {', '.join(videos)}"
            )
            continue
        for camera in report["cameras"]:
            for modality in report["modalities"]:
                shape = tuple(frame[schema.image_key(camera, modality)].shape)
                if shape != (3, report["height"], report["width"]):
                    problems.append(f"{root}: frame {index} {camera}_{modality} decodes to {shape}")
    return problems


def validate(cfg: DataCfg) -> list[str]:
    raw_dir, root = Path(cfg.raw_dir), Path(cfg.dataset_dir)
    checks = check_shards(raw_dir, cfg.robot, cfg.validate)
    problems = checks.problems
    episodes = sum(len(lengths) for lengths in checks.lengths.values())
    print(f"{len(checks.lengths)} readable shards, {episodes} episodes under {raw_dir}")
    print(f"replay of {checks.replayed} episodes: largest error {checks.worst:.3g}")
    if root.exists():
        problems += check_dataset(root, cfg.export.repo_id, cfg.robot, checks.lengths, cfg.validate)
    elif checks.lengths:
        print(f"no dataset at {root}; checked the shards only")
    else:
        problems.append(
            f"nothing to validate: no shards under {raw_dir / cfg.robot} and no dataset at {root}"
        )
    return problems


@hydra.main(config_path="../conf", config_name="data", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    quiet_video_libraries()
    problems = validate(to_dataclass(with_env_task(cfg), DataCfg).check())
    for problem in problems:
        print(f"PROBLEM {problem}", file=sys.stderr)
    print("valid" if not problems else f"{len(problems)} problems")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()

"""Reading an exported dataset's MobileMani metadata (episode sidecar and export report)."""

from __future__ import annotations

import json
from pathlib import Path

import av
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata
from lerobot.datasets.video_utils import FrameTimestampError

from mobilemani_data import schema
from mobilemani_rl.utils.errors import MissingFileError
from mobilemani_rl.utils.io import read_json


def read_episodes(root: Path) -> list[dict]:
    path = root / schema.EPISODES_FILE
    if not path.is_file():
        raise MissingFileError(
            f"{path} missing: {root} is not a MobileMani dataset (run mobilemani_data.export)"
        )
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def read_export_report(root: Path) -> dict:
    return read_json(root / schema.EXPORT_REPORT_FILE)


# What decoding a damaged video raises: PyAV's errors, or LeRobot's when a file cut short lacks the frames
# asked for.
VIDEO_DECODE_ERRORS = (av.error.FFmpegError, FrameTimestampError)

META_FILES = ("meta/info.json", "meta/tasks.parquet")  # LeRobot v3's metadata besides meta/episodes/


def open_dataset_metadata(repo_id: str, root: str | Path) -> LeRobotDatasetMetadata:
    """LeRobot's metadata of a local dataset whose every file is there. A missing file is named: LeRobot
    itself would fall back to the hub and fail offline, naming none."""
    root = Path(root)
    if not root.is_dir():
        raise MissingFileError(f"dataset {root} does not exist (`make data` exports one)")
    missing = [str(root / f) for f in META_FILES if not (root / f).is_file()]
    if not any((root / "meta" / "episodes").rglob("*.parquet")):
        missing.append(str(root / "meta/episodes/chunk-*/file-*.parquet"))
    if missing:
        raise MissingFileError(f"dataset {root} is missing {', '.join(missing)} (export it again)")
    meta = LeRobotDatasetMetadata(repo_id, root=root)
    if len(meta.episodes) != meta.total_episodes:
        raise MissingFileError(
            f"dataset {root}: meta/episodes holds {len(meta.episodes)} of the {meta.total_episodes} "
            "episodes meta/info.json lists; a file under meta/episodes is missing (export it again)"
        )
    check_dataset_files(meta)
    return meta


def check_dataset_files(meta: LeRobotDatasetMetadata) -> None:
    """Stop with the missing files' names when an episode's parquet or video file is gone
    (LeRobot itself would then try the hub and fail with an offline error that names neither)."""
    root = Path(meta.root)
    files = {root / meta.get_data_file_path(i) for i in range(meta.total_episodes)}
    files |= {
        root / meta.get_video_file_path(i, key) for i in range(meta.total_episodes) for key in meta.video_keys
    }
    missing = sorted(str(f) for f in files if not f.is_file())
    if missing:
        raise MissingFileError(
            f"dataset {root} is missing {len(missing)} file(s): {', '.join(missing[:5])}"
            f"{' ...' if len(missing) > 5 else ''} (export it again)"
        )

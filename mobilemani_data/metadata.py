"""Reading an exported dataset's MobileMani metadata (episode sidecar and export report)."""

from __future__ import annotations

import json
from pathlib import Path

from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata

from mobilemani_data import schema


def read_episodes(root: Path) -> list[dict]:
    path = root / schema.EPISODES_FILE
    if not path.is_file():
        raise FileNotFoundError(
            f"{path} missing: {root} is not a MobileMani dataset (run mobilemani_data.export)"
        )
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def read_export_report(root: Path) -> dict:
    return json.loads((root / schema.EXPORT_REPORT_FILE).read_text())


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
        raise FileNotFoundError(
            f"dataset {root} is missing {len(missing)} file(s): {', '.join(missing[:5])}"
            f"{' ...' if len(missing) > 5 else ''} (export it again)"
        )

"""Reading an exported dataset's MobileMani metadata (episode sidecar and export report)."""

from __future__ import annotations

import json
from pathlib import Path

from mobilemani_data import schema


def read_episodes(root: Path) -> list[dict]:
    path = root / schema.EPISODES_FILE
    if not path.is_file():
        raise FileNotFoundError(f"{path} missing: {root} is not a MobileMani dataset (run mobilemani_data.export)")
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def read_export_report(root: Path) -> dict:
    return json.loads((root / schema.EXPORT_REPORT_FILE).read_text())

"""Small file helpers every package uses: results that never appear half-written."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from mobilemani_rl.registry import InputError


def write_json_atomic(path: Path, payload: dict | list) -> None:
    """Write JSON to a temporary file, then rename it into place: readers see the old file or the new one."""
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(payload, indent=2))
    os.replace(tmp, path)


def read_json(path: Path) -> Any:
    """A JSON file the project or LeRobot wrote; one error naming it when it is damaged (writers replace their
    files whole, so the damage came from outside)."""
    try:
        return json.loads(path.read_text())
    except json.JSONDecodeError as err:
        raise InputError(
            f"{path} is damaged, not JSON ({err}); restore it, or rerun the stage that writes it"
        ) from err

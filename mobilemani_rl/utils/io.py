"""Small file helpers every package uses: results that never appear half-written, output locations checked
before any work starts, and the finite-values check every dataset stage applies (a NaN must never become a
training label)."""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from mobilemani_rl.utils.cli import file_in_the_way
from mobilemani_rl.utils.errors import InputError, UnwritableOutputError


def write_json_atomic(path: Path, payload: dict | list) -> None:
    """Write JSON to a temporary file, then rename it into place: readers see the old file or the new one."""
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(payload, indent=2))
    os.replace(tmp, path)


def replace_synced(tmp: Path, path: Path, synced: Path) -> None:
    """Rename `tmp` to `path` once `synced` (the file whose presence marks `tmp` complete) is on disk, so the
    final name never stands for something a crash could leave incomplete."""
    fd = os.open(synced, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
    os.replace(tmp, path)


def weights_sha256(directory: Path) -> str:
    """One sha256 over the bytes of a checkpoint directory's safetensors files, in name order: what identifies
    a model's weights, whatever path they are saved under (a retrained model reuses the old names)."""
    digest = hashlib.sha256()
    for path in sorted(directory.glob("*.safetensors")):
        with path.open("rb") as f:
            while chunk := f.read(1 << 20):
                digest.update(chunk)
    return digest.hexdigest()


def read_json(path: Path) -> Any:
    """A JSON file the project or LeRobot wrote; one error naming it when it is damaged (writers replace their
    files whole, so the damage came from outside)."""
    try:
        return json.loads(path.read_text())
    except json.JSONDecodeError as err:
        raise InputError(
            f"{path} is damaged, not JSON ({err}); restore it, or rerun the stage that writes it"
        ) from err


def check_writable(folder: Path | str, key: str) -> Path:
    """The output folder `folder` (set by the config key or option `key`) of a command that writes, checked
    before any work starts: UnwritableOutputError, one line naming it, when it cannot be made or written into
    (a file in its place or above it, a read-only file system, no permission). Nothing is left behind: the
    nearest existing folder on its way gets a probe file, created and removed at once; a real write, since
    os.access answers yes to root where root may not write (/sys). Every writing command calls this check."""
    folder = Path(folder)
    if (file := file_in_the_way(folder)) is not None:
        raise UnwritableOutputError(f"cannot write {folder} ({key}): {file} is a file; choose another path")
    existing = next(path for path in (folder, *folder.parents) if path.is_dir())
    try:
        handle, probe = tempfile.mkstemp(prefix=".write-probe-", dir=existing)
    except OSError as err:
        raise UnwritableOutputError(
            f"cannot write {folder} ({key}): {existing} is not writable ({err.strerror or err}); "
            "choose another path"
        ) from None
    os.close(handle)
    os.unlink(probe)
    return folder


def non_finite(arrays: Mapping[str, Any]) -> list[tuple[str, int, float]]:
    """(key, first row, its first bad value) of every floating-point array in `arrays` that holds a NaN or an
    infinity; the row counts along the first axis (a 1-d array's element). One vectorised pass per array."""
    found = []
    for key, values in arrays.items():
        values = np.asarray(values)
        if not np.issubdtype(values.dtype, np.floating):
            continue
        finite = np.isfinite(values)
        if finite.all():
            continue
        rows = finite.reshape(len(values), -1) if values.ndim else finite.reshape(1, 1)
        row = int(np.argmin(rows.all(axis=1)))
        bad = np.asarray(values.reshape(rows.shape)[row])[~rows[row]][0]
        found.append((key, row, float(bad)))
    return found

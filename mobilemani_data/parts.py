"""An export's parts: the subset's combinations in consecutive groups of `export.combinations_per_part`,
each rendered by one worker into a LeRobot dataset of its own under `<dataset>.parts/`, then merged into the
dataset.

A part is the unit an interrupted export keeps: it is written as `<part>.partial` and renamed when its
manifest (what it was rendered from, its episodes' metadata lines, what it left out) is in it, so a part
either exists complete or not at all; a rerun reuses every part whose manifest names the same shards and
settings and renders the others. Parts group the subset's combinations, not the shards found, so a shard
collected later changes only its own part.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from lerobot.datasets.aggregate import aggregate_datasets

from mobilemani_data.combos import shard_path
from mobilemani_rl.envs.tasks import Combination
from mobilemani_rl.utils.io import read_json, replace_synced

PARTS = ".parts"
PARTIAL = ".partial"
MANIFEST = "mobilemani_part.json"


@dataclass(frozen=True)
class Part:
    index: int  # the part's place among the subset's groups of combinations
    shards: tuple[Path, ...]  # the shards of its combinations that exist, in the subset's order

    @property
    def name(self) -> str:
        return f"part-{self.index:05d}"


def parts_dir(root: Path) -> Path:
    return root.with_name(root.name + PARTS)


def plan_parts(combos: list[Combination], raw_dir: Path, per_part: int) -> tuple[list[Part], int]:
    """The parts holding the combinations' existing shards, and how many combinations have none (not collected
    yet, or left out for a teacher that trained below teacher.min_train_success)."""
    parts, missing = [], 0
    for index, start in enumerate(range(0, len(combos), per_part)):
        paths = [raw_dir / shard_path(combo) for combo in combos[start : start + per_part]]
        found = tuple(path for path in paths if path.is_file())
        missing += len(paths) - len(found)
        if found:
            parts.append(Part(index, found))
    return parts, missing


def finished_manifest(folder: Path, source: dict) -> dict | None:
    """The manifest of the complete part at `folder` when it was rendered from `source`, else None."""
    path = folder / MANIFEST
    manifest = read_json(path) if path.is_file() else {}
    return manifest if manifest.get("source") == source else None


def seal_part(tmp: Path, folder: Path, manifest: dict) -> None:
    """Write the manifest into the rendered part `tmp`, then rename it to `folder`: the part is complete."""
    path = tmp / MANIFEST
    path.write_text(json.dumps(manifest, indent=1))
    replace_synced(tmp, folder, path)


def merge_parts(folders: list[Path], repo_id: str, root: Path) -> None:
    """One LeRobot dataset at `root` holding the parts' episodes in the order given. Each part's files are
    copied as they are (one video file per stream and one data file per part): appending them to shared
    files would rewrite each growing file once per part."""
    aggregate_datasets(
        [repo_id] * len(folders),
        repo_id,
        roots=folders,
        aggr_root=root,
        concatenate_videos=False,
        concatenate_data=False,
    )

"""Dataset statistics like the paper's table: episodes,
frames and mean episode length per skill, category, split.

    python -m mobilemani_data.stats robot=g1

Reads the exported dataset's episode metadata; prints a Markdown table and JSON (also written to
`meta/mobilemani_stats.json`).
"""

from __future__ import annotations

import json
from collections import defaultdict
from pathlib import Path

import hydra
from omegaconf import DictConfig

from mobilemani_data import schema
from mobilemani_data.config import DataCfg
from mobilemani_data.metadata import read_episodes
from mobilemani_rl.cli import entry_point
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.schema import to_dataclass

GROUPS = ("skill", "category", "split")
STATS_FILE = "meta/mobilemani_stats.json"


def _row(lengths: list[int]) -> dict:
    frames = sum(lengths)
    return {
        "episodes": len(lengths),
        "frames": frames,
        "mean_length": round(frames / len(lengths), 1),
        "mean_seconds": round(frames / len(lengths) / schema.FPS, 2),
    }


def dataset_stats(episodes: list[dict]) -> dict:
    table: dict[str, dict[str, dict]] = {}
    for key in GROUPS:
        groups: dict[str, list[int]] = defaultdict(list)
        for line in episodes:
            groups[str(line[key])].append(line["length"])
        table[key] = {name: _row(lengths) for name, lengths in sorted(groups.items())}
    table["total"] = {"all": _row([line["length"] for line in episodes])}
    table["objects"] = len({line["object_id"] for line in episodes})
    table["scenes"] = len({line["scene"] for line in episodes})
    table["tasks"] = len({line["instruction"] for line in episodes})
    return table


def markdown(table: dict) -> str:
    lines = [
        "| group | value | episodes | frames | mean length (frames) | mean length (s) |",
        "|---|---|---:|---:|---:|---:|",
    ]
    for key in (*GROUPS, "total"):
        for name, row in table[key].items():
            lines.append(
                f"| {key} | {name} | {row['episodes']} | {row['frames']} | {row['mean_length']} | "
                f"{row['mean_seconds']} |"
            )
    lines.append(f"\n{table['objects']} objects, {table['scenes']} scenes, {table['tasks']} instructions")
    return "\n".join(lines)


@hydra.main(config_path="../conf", config_name="data", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    root = Path(to_dataclass(with_env_task(cfg), DataCfg).check_counts().dataset_dir)
    table = dataset_stats(read_episodes(root))
    (root / STATS_FILE).write_text(json.dumps(table, indent=2))
    print(json.dumps(table, indent=2))
    print(markdown(table))


if __name__ == "__main__":
    main()

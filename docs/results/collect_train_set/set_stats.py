"""The paper-style statistics of a collected set from its raw shards, before any export:

    python docs/results/collect_train_set/set_stats.py <data_dir>/raw g1 > set_stats.json

The same table as `mobilemani_data.stats` (episodes, frames and mean length per skill, category and split;
the teacher's action roughness), which reads an exported dataset; rendering the whole train set into one takes
far longer than collecting it. Adds each skill's collection yield: successful episodes kept per attempt.
"""

import collections
import json
import sys
from pathlib import Path

import h5py
import numpy as np

from mobilemani_data.shards import shard_paths
from mobilemani_data.stats import GROUPS, action_roughness, dataset_stats, markdown


def main(raw_dir: str, robot: str) -> dict:
    episodes, actions, episode_index = [], [], []
    attempts: dict[str, list[int]] = collections.defaultdict(lambda: [0, 0])  # skill: [kept, attempts]
    paths = shard_paths(Path(raw_dir), robot)
    for path in paths:
        with h5py.File(path, "r") as f:
            header = dict(f.attrs)
            meta = {key: str(header[key]) for key in (*GROUPS, "object_id", "scene", "instruction")}
            attempts[meta["skill"]][0] += int(header["collected"])
            attempts[meta["skill"]][1] += int(header["attempts"])
            for name in sorted(k for k in f if k.startswith("episode_")):
                episodes.append({**meta, "length": int(f[name].attrs["length"])})
                actions.append(f[name]["action"][()])
                episode_index.append(np.full(len(actions[-1]), len(episodes)))
    table = dataset_stats(episodes)
    table["action_roughness"] = action_roughness(np.concatenate(actions), np.concatenate(episode_index))
    table["yield"] = {skill: round(kept / tried, 3) for skill, (kept, tried) in sorted(attempts.items())}
    table["shards"] = len(paths)
    print(markdown(table), file=sys.stderr)
    return table


if __name__ == "__main__":
    print(json.dumps(main(*sys.argv[1:]), indent=1))

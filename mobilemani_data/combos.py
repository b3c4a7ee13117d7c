"""Data-side naming of task combinations: shard paths and the round-robin split of work between jobs."""

from __future__ import annotations

from pathlib import PurePosixPath

from mobilemani_data.config import ShardCfg
from mobilemani_rl.envs.tasks import Combination
from mobilemani_rl.utils.errors import InputError


def shard_path(combo: Combination) -> PurePosixPath:
    """Relative shard path: <robot>/<category>/<index>/<skill>/<setting>_<NN>.h5."""
    return PurePosixPath(combo.robot, combo.object_id, combo.skill, combo.scene.replace("/", "_") + ".h5")


def shard_of(combos: list[Combination], shard: ShardCfg) -> list[Combination]:
    """Round-robin share of one job, so that jobs get similar mixes of categories."""
    if not 0 <= shard.index < shard.count:
        raise InputError(f"shard.index must be in [0, {shard.count}), got {shard.index}")
    return combos[shard.index :: shard.count]

"""A training run's directory: its config, checkpoints, curve and completion marker.

A run directory is complete only once `result.json` exists (written atomically last), so an interrupted run
never looks finished; rerunning resumes from the newest checkpoint with the saved config, or from the finished
warm start (`warm_start.pt`, written atomically once it is done) when PPO has saved none yet.
"""

from __future__ import annotations

import copy
import re
from pathlib import Path

from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.registry import ConfigMismatchError
from mobilemani_rl.schema import changed_values

CONFIG = "config.yaml"
RESULT = "result.json"
CURVE = "curve.json"
WARM_START = "warm_start.json"  # behaviour-cloning statistics, when the run started from the scripted policy
WARM_START_CHECKPOINT = (
    "warm_start.pt"  # the runner right after the warm start (minutes of work a rerun keeps)
)
_CHECKPOINT = re.compile(r"model_(\d+)\.pt$")


def checkpoints(run_dir: Path) -> list[Path]:
    """The run's PPO checkpoints, newest first."""
    found = [(int(m.group(1)), p) for p in run_dir.glob("model_*.pt") if (m := _CHECKPOINT.search(p.name))]
    return [p for _, p in sorted(found, reverse=True)]


def latest_checkpoint(run_dir: Path) -> Path | None:
    found = checkpoints(run_dir)
    return found[0] if found else None


def is_complete(run_dir: Path) -> bool:
    return (run_dir / RESULT).exists()


def save_or_check_config(
    run_dir: Path,
    cfg: DictConfig,
    keys: tuple[str, ...],
    defaults: dict | None = None,
    placement: tuple[str, ...] = (),
) -> None:
    """Store the (resolved) config of a new run; for an existing run, require the same values under `keys`. A
    run that stopped before its first checkpoint (or its finished warm start) has nothing to resume, so its
    config is simply replaced. A key the saved config lacks (it was added to the schema later) counts as its
    value in `defaults`, the value the run was trained with. The dotted `placement` keys say where the run
    computes, not what it learns: a change there is reported and the run resumes (a run started on a GPU node
    can go on on a laptop); the saved config keeps its first values."""
    path = run_dir / CONFIG
    current = OmegaConf.create(OmegaConf.to_container(cfg, resolve=True))
    if not path.exists() or (
        latest_checkpoint(run_dir) is None and not (run_dir / WARM_START_CHECKPOINT).exists()
    ):
        run_dir.mkdir(parents=True, exist_ok=True)
        OmegaConf.save(current, path)
        return
    saved = OmegaConf.merge(OmegaConf.create(defaults or {}), OmegaConf.load(path))
    saved, wanted = OmegaConf.to_container(saved), OmegaConf.to_container(current)
    if moved := changed_values(saved, wanted, placement):
        print(f"resuming {run_dir} with another placement ({'; '.join(moved)})")
    saved, wanted = _without(saved, placement), _without(wanted, placement)
    per_key = {k: changed_values(saved, wanted, (k,)) for k in keys}
    if differing := [k for k, changes in per_key.items() if changes]:
        changes = [change for k in differing for change in per_key[k]]
        raise ConfigMismatchError(
            f"{run_dir} was started with a different {', '.join(differing)} config ({'; '.join(changes)}); "
            f"resume with the saved {path} or choose another run_dir"
        )


def _without(cfg: dict, dotted_keys: tuple[str, ...]) -> dict:
    """A copy of a plain nested config without the leaves at `dotted_keys`."""
    cfg = copy.deepcopy(cfg)
    for dotted in dotted_keys:
        *parents, leaf = dotted.split(".")
        node = cfg
        for part in parents:
            node = node.get(part) if isinstance(node, dict) else None
        if isinstance(node, dict):
            node.pop(leaf, None)
    return cfg

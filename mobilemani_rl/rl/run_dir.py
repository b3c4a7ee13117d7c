"""A training run's directory: its config, checkpoints, curve and completion marker.

A run directory is complete only once `result.json` exists (written atomically last), so an interrupted run
never looks finished; rerunning resumes from the newest checkpoint with the saved config, or from the finished
warm start (`warm_start.pt`, written atomically once it is done) when PPO has saved none yet.
"""

from __future__ import annotations

import copy
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.utils.config_store import changed_values, dotted_value
from mobilemani_rl.utils.errors import ConfigMismatchError

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


@dataclass(frozen=True)
class ConfigRules:
    """What may differ between a run directory's saved config and the config a rerun asks for.

    Every leaf under the dotted `keys` must match. A key the saved config lacks (it was added to the schema
    later) counts as its value in `defaults`, the value the run was trained with. The dotted `placement` keys
    say where the run computes, not what it learns: a run started on a GPU node can go on on a laptop. The
    dotted `budgets` (an iteration count) may only grow: the run, finished or not, goes on to the larger
    value.
    """

    keys: tuple[str, ...]
    defaults: dict | None = None
    placement: tuple[str, ...] = ()
    budgets: tuple[str, ...] = ()


@dataclass
class RunCheck:
    """How a run directory's saved config stands against the config asked for now."""

    saved: DictConfig | None = None  # the saved config as stored; None: nothing to resume
    moved: list[str] = field(default_factory=list)  # placement changes: reported, the saved values kept
    grown: dict[str, object] = field(default_factory=dict)  # budgets raised: dotted key -> the larger value

    @property
    def fresh(self) -> bool:
        """Nothing to resume: the asked config is simply (re)written."""
        return self.saved is None


def check_config(run_dir: Path, cfg: DictConfig, rules: ConfigRules) -> RunCheck:
    """Compare a run directory's saved config with `cfg` under `rules`, writing nothing; a change the run
    cannot take raises ConfigMismatchError naming each changed key. A run that stopped before its first
    checkpoint (or its finished warm start) has nothing to resume, so any config is fine."""
    path = run_dir / CONFIG
    if not path.exists() or (
        latest_checkpoint(run_dir) is None and not (run_dir / WARM_START_CHECKPOINT).exists()
    ):
        return RunCheck()
    stored = OmegaConf.load(path)
    saved = OmegaConf.to_container(OmegaConf.merge(OmegaConf.create(rules.defaults or {}), stored))
    wanted = OmegaConf.to_container(cfg, resolve=True)
    moved = changed_values(saved, wanted, rules.placement)
    grown = {
        key: dotted_value(wanted, key)
        for key in rules.budgets
        if _larger(dotted_value(wanted, key), dotted_value(saved, key))
    }
    free = (*rules.placement, *grown)
    saved, wanted = _without(saved, free), _without(wanted, free)
    per_key = {k: changed_values(saved, wanted, (k,)) for k in rules.keys}
    if differing := [k for k, changes in per_key.items() if changes]:
        changes = [change for k in differing for change in per_key[k]]
        raise ConfigMismatchError(
            f"{run_dir} was started with a different {', '.join(differing)} config ({'; '.join(changes)}); "
            f"resume with the saved {path}{_budget_hint(rules.budgets)} or choose another run_dir"
        )
    return RunCheck(saved=stored, moved=moved, grown=grown)


def save_or_check_config(run_dir: Path, cfg: DictConfig, rules: ConfigRules) -> None:
    """`check_config`, then store what it allows: a new run's config, or a raised budget (a finished run is
    finished no more). Placement changes are reported and the saved config keeps its first values."""
    check = check_config(run_dir, cfg, rules)
    if check.fresh:
        run_dir.mkdir(parents=True, exist_ok=True)
        _save_atomic(OmegaConf.create(OmegaConf.to_container(cfg, resolve=True)), run_dir / CONFIG)
        return
    if check.moved:
        print(f"resuming {run_dir} with another placement ({'; '.join(check.moved)})")
    if check.grown:
        # the result first: cut short between the two, the run is unfinished and the same command continues it
        (run_dir / RESULT).unlink(missing_ok=True)
        for key, value in check.grown.items():
            OmegaConf.update(check.saved, key, value)
        _save_atomic(check.saved, run_dir / CONFIG)
        print(f"continuing {run_dir} to {', '.join(f'{k}={v}' for k, v in check.grown.items())}")


def _larger(wanted: object, saved: object) -> bool:
    return isinstance(wanted, int) and isinstance(saved, int) and wanted > saved


def _budget_hint(budgets: tuple[str, ...]) -> str:
    return f" (only {', '.join(budgets)} may grow)" if budgets else ""


def _save_atomic(cfg: DictConfig, path: Path) -> None:
    tmp = path.with_suffix(path.suffix + ".tmp")
    OmegaConf.save(cfg, tmp)
    os.replace(tmp, path)


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

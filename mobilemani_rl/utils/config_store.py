"""Dataclasses are the configs' one source of defaults: each entry point's root YAML (conf/) extends a
structured-config schema registered here, and its composed config converts back to a dataclass.

The data and VLA packages register their schemas through this module too (they may import mobilemani_rl;
it never imports them).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from hydra.core.config_store import ConfigStore
from omegaconf import DictConfig, OmegaConf

CONF_DIR = Path(__file__).resolve().parents[2] / "conf"  # the Hydra configs every entry point composes


def group_options(group: str) -> list[str]:
    """The options of a config group (`conf/<group>/*.yaml`), for a command line's choices."""
    return sorted(p.stem for p in (CONF_DIR / group).glob("*.yaml"))


def register_schema(name: str, schema: type) -> None:
    """Make `schema` a root config named `name`, for a root YAML's `defaults: [<name>, ...]`."""
    ConfigStore.instance().store(name=name, node=schema)


def to_dataclass[T](cfg: DictConfig | dict[str, Any], schema: type[T], ignore: tuple[str, ...] = ()) -> T:
    """A composed config (interpolations resolved, Hydra's own block and `ignore` dropped) as `schema`.

    A key the schema lacks raises omegaconf's ConfigKeyError naming it; missing keys take the defaults.
    """
    plain = OmegaConf.to_container(cfg, resolve=True) if isinstance(cfg, DictConfig) else dict(cfg)
    for key in ("hydra", *ignore):
        plain.pop(key, None)
    return OmegaConf.to_object(OmegaConf.merge(OmegaConf.structured(schema), plain))


def dotted_value(cfg: dict[str, Any], dotted: str) -> object:
    """The value at a dotted key of a plain nested config (None where the path does not exist)."""
    node: object = cfg
    for part in dotted.split("."):
        node = node.get(part) if isinstance(node, dict) else None
    return node


def changed_values(old: dict[str, Any], new: dict[str, Any], keys: tuple[str, ...]) -> list[str]:
    """'key.path: old -> new' for every leaf under the (dotted) `keys` whose value differs between two plain
    configs."""

    def leaves(prefix: str, value: object, out: dict[str, object]) -> dict[str, object]:
        if isinstance(value, dict):
            for k, v in value.items():
                leaves(f"{prefix}.{k}", v, out)
        else:
            out[prefix] = value
        return out

    before: dict[str, object] = {}
    after: dict[str, object] = {}
    for key in keys:
        leaves(key, dotted_value(old, key), before)
        leaves(key, dotted_value(new, key), after)
    return [
        f"{k}: {before.get(k)} -> {after.get(k)}"
        for k in sorted(before.keys() | after.keys())
        if before.get(k) != after.get(k)
    ]

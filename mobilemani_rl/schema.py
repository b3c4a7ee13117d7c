"""Dataclasses are the configs' one source of defaults: each entry point's root YAML (conf/) extends a
structured-config schema registered here, and its composed config converts back to a dataclass.

The data and VLA packages register their schemas through this module too (they may import mobilemani_rl;
it never imports them).
"""

from __future__ import annotations

from typing import Any

from hydra.core.config_store import ConfigStore
from omegaconf import DictConfig, OmegaConf


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

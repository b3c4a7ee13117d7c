"""Small configs shared by the dataset tests."""

from __future__ import annotations

from pathlib import Path

from checkout import ROOT
from hydra import compose, initialize_config_dir

from mobilemani_data.config import DataCfg
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.utils.config_store import to_dataclass

CONF = ROOT / "conf"


def tiny_cfg(workdir: Path, *overrides: str) -> DataCfg:
    """The tiny subset (2 objects x 2 skills x 2 scenes x 2 episodes), 64 px H.264 export, under `workdir`."""
    with initialize_config_dir(config_dir=str(CONF), version_base="1.3"):
        cfg = compose(
            "data",
            overrides=[
                "data/subset=tiny",
                f"data_dir={workdir}",
                "collect.num_envs=8",
                "export.width=64",
                "export.height=64",
                "export.vcodec=h264",
                *overrides,
            ],
        )
    return to_dataclass(with_env_task(cfg), DataCfg).check()

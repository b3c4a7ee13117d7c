"""The Hydra YAML tree takes its defaults from the dataclass configs."""

import pytest
from checkout import ROOT
from hydra import compose, initialize_config_dir
from omegaconf.errors import ConfigKeyError

from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.rl.config import RLCfg
from mobilemani_rl.utils.config_store import to_dataclass

CONF = str(ROOT / "conf")


def compose_rl(overrides: list[str]):
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        return compose(config_name="rl", overrides=overrides)


def test_default_yaml_equals_dataclass_defaults():
    cfg = to_dataclass(compose_rl([]), RLCfg).env_cfg()
    assert cfg == EnvCfg()


def test_overrides_reach_the_env_config():
    cfg = to_dataclass(
        compose_rl(
            [
                "robot=xhand",
                "task.object=test/can",
                "task.skill=pick",
                "env.num_envs=8",
                "env.physics.substeps=4",
            ]
        ),
        RLCfg,
    ).env_cfg()
    assert cfg.task == TaskCfg(robot="xhand", object="test/can", skill="pick")
    assert cfg.num_envs == 8 and cfg.physics.substeps == 4


def test_unknown_key_is_an_error():
    with pytest.raises(ConfigKeyError, match="warp_speed"):
        to_dataclass({"env": {"physics": {"warp_speed": 9}}}, RLCfg)

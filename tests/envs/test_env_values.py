"""Env values are checked by the env and by every entry point that composes an env block, each bad value
named by its key, before anything is written."""

import pytest
from data_helpers import tiny_cfg
from omegaconf import OmegaConf
from roots import compose_root

from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv


@pytest.mark.parametrize(
    ("override", "named"),
    [
        # each reached a library's traceback (ZeroDivisionError, numpy's "high - low < 0", "all input arrays
        # must have the same shape") or ran without a word, never able to succeed or to observe anything
        ("env.physics.control_hz=0", r"env.physics.control_hz=0.0 \(above 0\)"),
        ("env.physics.solver_iterations=0", "env.physics.solver_iterations=0"),
        ("env.physics.nthread=-1", r"env.physics.nthread=-1 \(>= 0\)"),
        ("env.seed=-1", r"env.seed=-1 \(an integer >= 0\)"),
        ("env.success.threshold=0", r"env.success.threshold=0.0 \(above 0\)"),
        ("env.success.hold_steps=0", "env.success.hold_steps=0"),
        ("env.obs_clip=0", r"env.obs_clip=0.0 \(above 0\)"),
        ("env.actions.ik_damping=-1", r"env.actions.ik_damping=-1.0 \(>= 0\)"),
        ("env.reset.random_height=-0.5", r"env.reset.random_height=-0.5 \(>= 0\)"),
        (
            "env.reset.root_x_range=[0.25,-0.25]",
            r"env.reset.root_x_range=\[0.25, -0.25\] \(\[low, high\] with low <= high\)",
        ),
        ("env.reset.room_jitter_y=[0.1]", r"env.reset.room_jitter_y=\[0.1\] \(\[low, high\]"),
    ],
)
def test_env_values_are_checked_by_every_entry_point_and_the_env(tmp_path, override, named):
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.rl.train import train
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.eval.config import EvalCfg

    with pytest.raises(InputError, match=named):
        train(compose_root("rl", ["rl/ppo=tiny", f"run_dir={tmp_path / 'run'}", override]))
    with pytest.raises(InputError, match=named):
        tiny_cfg(tmp_path / "data", override)
    with pytest.raises(InputError, match=named):
        to_dataclass(with_env_task(compose_root("eval", [override])), EvalCfg).check()
    key, value = override.split("=")
    env_cfg = OmegaConf.merge(OmegaConf.structured(EnvCfg), OmegaConf.from_dotlist([f"{key[4:]}={value}"]))
    with pytest.raises(InputError, match=named):
        MobileManiEnv(OmegaConf.to_object(env_cfg))
    assert not any(tmp_path.iterdir())


def test_env_keys_that_data_and_evaluation_set_are_refused(tmp_path):
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_vla.eval.config import EvalCfg

    with pytest.raises(ValueError, match=r"env.seed=3 \(set it through collect.seed\)"):
        tiny_cfg(tmp_path, "env.seed=3")
    cfg = compose_root("eval", ["env.num_envs=4"])
    with pytest.raises(ValueError, match=r"env.num_envs=4 \(set it through episodes_per_batch\)"):
        to_dataclass(with_env_task(cfg), EvalCfg).check()

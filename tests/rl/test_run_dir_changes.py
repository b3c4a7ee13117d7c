"""A resumed PPO run keeps what it learns with: a changed setting is refused by name, where it computes
may change, and a key added since it started counts as its default."""

import pytest
from omegaconf import OmegaConf
from roots import compose_root


def test_a_changed_run_names_each_changed_key(tmp_path):
    from mobilemani_rl.rl.run_dir import ConfigRules, save_or_check_config
    from mobilemani_rl.utils.errors import ConfigMismatchError

    run_dir, rules = tmp_path / "run", ConfigRules(("rl",))
    save_or_check_config(run_dir, compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"]), rules)
    (run_dir / "model_2.pt").touch()  # it has something to resume
    changed = compose_root(
        "rl", ["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.learning_rate=0.5", "rl.ppo.num_envs=16"]
    )
    each = r"\(rl.ppo.learning_rate: 0.001 -> 0.5; rl.ppo.num_envs: 8 -> 16\)"
    with pytest.raises(ConfigMismatchError, match=each):
        save_or_check_config(run_dir, changed, rules)


def test_a_resumed_run_may_move_devices_but_not_change_what_it_learns(tmp_path, capsys):
    """Where PPO computes (device, threads, physics threads) may change between pieces of one run, e.g. a run
    started on a GPU node goes on on a laptop; the saved config keeps the first values, and any learning
    setting is refused."""
    from mobilemani_rl.rl.run_dir import ConfigRules, save_or_check_config
    from mobilemani_rl.rl.train import PLACEMENT_KEYS
    from mobilemani_rl.utils.errors import ConfigMismatchError

    run_dir, rules = tmp_path / "run", ConfigRules(("env", "rl"), placement=PLACEMENT_KEYS)
    save_or_check_config(run_dir, compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"]), rules)
    (run_dir / "model_2.pt").touch()  # it has something to resume
    moved = [
        "rl/ppo=tiny",
        f"run_dir={run_dir}",
        "rl.ppo.device=cuda",
        "rl.ppo.update_threads=16",
        "env.physics.nthread=1",
    ]
    save_or_check_config(run_dir, compose_root("rl", moved), rules)
    moves = capsys.readouterr().out
    assert "rl.ppo.device: cpu -> cuda; rl.ppo.update_threads: 0 -> 16" in moves
    assert "env.physics.nthread: 0 -> 1" in moves
    assert OmegaConf.load(run_dir / "config.yaml").rl.ppo.device == "cpu"
    changed = compose_root("rl", [*moved, "rl.ppo.learning_rate=0.5"])
    with pytest.raises(ConfigMismatchError, match=r"\(rl.ppo.learning_rate: 0.001 -> 0.5\)"):
        save_or_check_config(run_dir, changed, rules)


def test_a_run_saved_before_a_key_existed_resumes_with_its_default(tmp_path):
    """A run started before `rl.ppo.precision` existed trained in fp32, the default: it resumes with that
    value and refuses another, naming it."""
    from mobilemani_rl.rl.config import RLCfg
    from mobilemani_rl.rl.run_dir import ConfigRules, save_or_check_config
    from mobilemani_rl.utils.errors import ConfigMismatchError

    run_dir = tmp_path / "run"
    save_or_check_config(
        run_dir, compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"]), ConfigRules(("rl",))
    )
    saved = OmegaConf.load(run_dir / "config.yaml")
    del saved.rl.ppo["precision"]  # what an older version wrote
    OmegaConf.save(saved, run_dir / "config.yaml")
    (run_dir / "model_2.pt").touch()  # it has something to resume
    rules = ConfigRules(("rl",), defaults=OmegaConf.to_container(OmegaConf.structured(RLCfg)))
    resumed = compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}"])
    save_or_check_config(run_dir, resumed, rules)
    changed = compose_root("rl", ["rl/ppo=tiny", f"run_dir={run_dir}", "rl.ppo.precision=bf16"])
    with pytest.raises(ConfigMismatchError, match=r"\(rl.ppo.precision: fp32 -> bf16\)"):
        save_or_check_config(run_dir, changed, rules)

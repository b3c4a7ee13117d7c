"""One teacher loader for evaluation, data and the harness; checkpoints load as tensors only."""

import pickle
import shutil
from pathlib import Path

import pytest
import torch
from hydra import compose, initialize_config_dir

from mobilemani_rl.rl.run_dir import CONFIG
from mobilemani_rl.teacher import (
    TeacherPolicy,
    load_teacher,
    newest_checkpoint,
    teacher_run_dir,
    trained_success,
)
from mobilemani_rl.train import train

CONF = str(Path(__file__).resolve().parents[1] / "conf")


@pytest.fixture(scope="module")
def trained_run(tmp_path_factory) -> tuple[Path, str, str, str]:
    """A tiny PPO run laid out as `make rl` lays it out: <runs_dir>/<robot>/<object>/<skill>."""
    runs_dir = tmp_path_factory.mktemp("runs")
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        cfg = compose(config_name="rl", overrides=["rl/ppo=tiny", f"run_dir={runs_dir / 'g1/test/box/open'}",
                                                   "eval_episodes=0"])
    train(cfg)
    return runs_dir, "g1", "test/box", "open"


class _RunsCode:
    def __reduce__(self):
        return (exec, ("open('PWNED', 'w').write('x')",))


def test_loader_finds_loads_and_refuses_code(trained_run, tmp_path, monkeypatch):
    runs_dir, robot, object_id, skill = trained_run
    run_dir = teacher_run_dir(runs_dir, robot, object_id, skill)
    checkpoint = newest_checkpoint(run_dir)
    assert 0.0 <= trained_success(run_dir) <= 1.0 and trained_success(tmp_path) is None
    env, actor = load_teacher(checkpoint, num_envs=3)
    actions = TeacherPolicy(env, actor)()
    assert actions.shape == (3, env.num_actions) and torch.isfinite(torch.as_tensor(actions)).all()

    with pytest.raises(FileNotFoundError, match="no teacher checkpoint"):
        newest_checkpoint(tmp_path)
    crafted = tmp_path / "run"
    shutil.copytree(run_dir, crafted)
    bad = newest_checkpoint(crafted)
    bad.write_bytes(pickle.dumps({"model_state_dict": _RunsCode()}))
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=str(bad)):
        load_teacher(bad, num_envs=1)
    assert not (tmp_path / "PWNED").exists()
    (crafted / CONFIG).unlink()
    with pytest.raises(FileNotFoundError, match=CONFIG):
        load_teacher(bad, num_envs=1)

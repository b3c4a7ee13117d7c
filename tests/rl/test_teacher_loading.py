"""One teacher loader for evaluation, data and the harness; checkpoints load as tensors only."""

import json
import pickle
import shutil
from pathlib import Path

import pytest
import torch
from checkout import ROOT
from data_helpers import tiny_cfg
from hydra import compose, initialize_config_dir
from payload import PlantedCode

from mobilemani_data.collect import check_complete_shards, collect
from mobilemani_data.teachers import build_teacher, teachable_combinations
from mobilemani_rl.assets.objects import catalog_ids
from mobilemani_rl.envs.tasks import Combination, select_combinations
from mobilemani_rl.rl.run_dir import CONFIG, RESULT, latest_checkpoint
from mobilemani_rl.rl.teacher import (
    TeacherPolicy,
    find_teacher_checkpoint,
    load_teacher,
    teacher_run_dir,
    trained_success,
)
from mobilemani_rl.rl.train import train
from mobilemani_rl.utils.errors import ConfigMismatchError

CONF = str(ROOT / "conf")


@pytest.fixture(scope="module")
def trained_run(tmp_path_factory) -> tuple[Path, str, str, str]:
    """A tiny PPO run laid out as `make rl` lays it out: <runs_dir>/<robot>/<object>/<skill>."""
    runs_dir = tmp_path_factory.mktemp("runs")
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        cfg = compose(
            config_name="rl",
            overrides=["rl/ppo=tiny", f"run_dir={runs_dir / 'g1/test/box/open'}", "eval_episodes=0"],
        )
    train(cfg)
    return runs_dir, "g1", "test/box", "open"


def test_loader_finds_loads_and_refuses_code(trained_run, tmp_path):
    runs_dir, robot, object_id, skill = trained_run
    run_dir = teacher_run_dir(runs_dir, robot, object_id, skill)
    checkpoint = find_teacher_checkpoint(runs_dir, robot, object_id, skill)
    assert checkpoint == latest_checkpoint(run_dir)
    assert 0.0 <= trained_success(run_dir) <= 1.0 and trained_success(tmp_path) is None
    env, actor = load_teacher(checkpoint, num_envs=3)
    actions = TeacherPolicy(env, actor)()
    assert actions.shape == (3, env.num_actions) and torch.isfinite(torch.as_tensor(actions)).all()

    with pytest.raises(FileNotFoundError, match="no teacher checkpoint .* nor in its category's run"):
        find_teacher_checkpoint(tmp_path, robot, object_id, skill)
    crafted = tmp_path / "run"
    shutil.copytree(run_dir, crafted)
    bad = latest_checkpoint(crafted)
    bad.write_bytes(pickle.dumps({"model_state_dict": PlantedCode(tmp_path / "PWNED")}))
    with pytest.raises(ValueError, match=f"{bad}: UnpicklingError: Weights only load failed$"):
        load_teacher(bad, num_envs=1)
    assert not (tmp_path / "PWNED").exists()
    (crafted / CONFIG).unlink()
    with pytest.raises(FileNotFoundError, match=CONFIG):
        load_teacher(bad, num_envs=1)


def test_collection_falls_back_to_the_category_teacher_and_says_how_to_keep_a_weak_one(tmp_path, capsys):
    """`make rl OBJECT=box` trains one policy for the category;
    collection on any box without its own run uses it."""
    runs_dir = tmp_path / "runs"
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        cfg = compose(
            config_name="rl",
            overrides=[
                "rl/ppo=tiny",
                f"run_dir={runs_dir / 'g1/box/open'}",
                "task.object=box",
                "objects_per_policy=2",
                "rl.ppo.max_iterations=1",
            ],
        )
    train(cfg)
    object_id = catalog_ids("box", "test")[0]  # never trained on, and no run of its own
    checkpoint = find_teacher_checkpoint(runs_dir, "g1", object_id, "open")
    assert checkpoint.parent == runs_dir / "g1/box/open"
    data = tiny_cfg(
        tmp_path / "data",
        "data/teacher=ppo",
        f"teacher.runs_dir={runs_dir}",
        f"subset.objects=[{object_id}]",
        "subset.skills=[open]",
        "subset.scenes_per_object=1",
    )
    combo = select_combinations(data.robot, data.subset)[0]
    teacher = build_teacher(data.teacher, combo, data.env, 2, seed=0)
    # one object, not the category
    assert teacher.name == str(checkpoint) and teacher.env.cfg.task.object == object_id
    assert teacher.policy().shape == (2, teacher.env.num_actions)

    assert teachable_combinations(data.teacher, [combo]) == ([combo], [])

    result = checkpoint.parent / RESULT
    result.write_text(json.dumps({**json.loads(result.read_text()), "train_success": 0.05}))
    kept, notes = teachable_combinations(data.teacher, [combo])
    assert kept == [] and notes == [
        f"left out: {checkpoint.parent} trained to success 0.05 < teacher.min_train_success=0.1 (lower it, "
        "e.g. teacher.min_train_success=0, to collect with it anyway)"
    ]
    capsys.readouterr()  # drop training's output
    (path,) = collect(data)
    assert not path.exists() and not list(Path(data.raw_dir).rglob("*.h5*"))
    assert capsys.readouterr().out.splitlines() == [
        "1 combinations: 0 complete, 1 left out, 0 to collect",
        *notes,
    ]
    data.teacher.min_train_success = 0.0
    assert teachable_combinations(data.teacher, [combo]) == ([combo], [])


def test_a_complete_shard_of_an_earlier_ppo_teacher_is_not_taken_for_the_newer_ones(tmp_path):
    """A rerun skips complete shards: after the teacher trained on, they would pass for its newer ones."""
    runs_dir = tmp_path / "runs"
    run = ["rl/ppo=tiny", f"run_dir={runs_dir / 'g1/box/open'}", "task.object=box", "objects_per_policy=2"]
    with initialize_config_dir(config_dir=CONF, version_base="1.3"):
        first, more = (
            compose(config_name="rl", overrides=[*run, f"rl.ppo.max_iterations={n}"]) for n in (1, 2)
        )
    train(first)
    object_id = catalog_ids("box", "test")[0]
    older = find_teacher_checkpoint(runs_dir, "g1", object_id, "open")
    data = tiny_cfg(tmp_path / "data", "data/teacher=ppo", f"teacher.runs_dir={runs_dir}")
    combo = Combination("g1", object_id, "box", "open", "tabletop/00", "test", "train")
    header = {"requested": data.subset.episodes, "seed": combo.seed(data.collect.seed), "teacher": str(older)}
    check_complete_shards(data, [(combo, tmp_path / "shard.h5", header)])  # the teacher it names: complete
    train(more)
    newer = find_teacher_checkpoint(runs_dir, "g1", object_id, "open")
    with pytest.raises(ConfigMismatchError, match=f"\\(teacher: {older} -> {newer}\\)"):
        check_complete_shards(data, [(combo, tmp_path / "shard.h5", header)])
    (runs_dir / "g1/box/open").rename(tmp_path / "gone")  # a shard whose teacher is gone stays complete
    check_complete_shards(data, [(combo, tmp_path / "shard.h5", header)])

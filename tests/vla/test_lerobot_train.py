"""The lerobot-train wrapper: its own flag, the arguments it checks before LeRobot starts, and how a rerun
on a run directory continues."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from mobilemani_rl.utils.errors import ConfigMismatchError, InputError, OutputExistsError
from mobilemani_vla.data.synthetic import write_synthetic_dataset
from mobilemani_vla.lerobot_presets import RUN_FLAGS, SMOLVLM_DIR
from mobilemani_vla.lerobot_train import (
    LAST,
    check_arguments,
    continued,
    frame_cache_flag,
    keep_last_checkpoint,
    trained_step,
    with_preset,
)


def test_frame_cache_flag_is_taken_out_of_lerobots_arguments():
    assert frame_cache_flag(["--policy.type=act"]) == (True, ["--policy.type=act"])
    assert frame_cache_flag(["--frame_cache=false", "--steps=3"]) == (False, ["--steps=3"])
    with pytest.raises(InputError, match="--frame_cache=yes: give --frame_cache=true"):
        frame_cache_flag(["--frame_cache=yes"])


def test_the_dataset_given_to_lerobot_train_is_checked_before_lerobot_opens_it(tmp_path):
    """LeRobot falls back to the hub for a missing local file and fails offline, naming none."""
    nowhere = tmp_path / "nowhere"
    for given in ([f"--dataset.root={nowhere}"], ["--dataset.root", str(nowhere)]):  # both of LeRobot's forms
        with pytest.raises(FileNotFoundError, match=f"dataset {nowhere} does not exist"):
            check_arguments(["--policy.type=act", "--dataset.streaming", *given])
    root = write_synthetic_dataset(tmp_path / "g1", episodes=1, length=5)
    check_arguments([f"--dataset.root={root}", "--dataset.repo_id=mobilemani/g1"])
    (root / "meta" / "info.json").unlink()
    with pytest.raises(FileNotFoundError, match="meta/info.json"):
        check_arguments([f"--dataset.root={root}"])
    check_arguments(["--resume=true", "--config_path=train_config.json"])  # its config names the dataset


@pytest.mark.parametrize("given", [["--steps=0"], ["--batch_size", "0"], ["--steps=abc"], ["--steps=-2"]])
def test_lerobot_trains_only_with_counts_of_at_least_one(given):
    """`make lerobot LEROBOT_STEPS=0` trained nothing, exited 0 and left evaluation to find no checkpoint."""
    key = given[0].split("=")[0]
    with pytest.raises(InputError, match=f"invalid values: {key}=.* \\(a whole number of at least 1\\)"):
        check_arguments(["--policy.type=act", *given])
    check_arguments(["--steps=3", "--batch_size=16"])


def trained_run(run: Path, step: int, steps: int, root: str = "data/lerobot") -> Path:
    """What lerobot-train leaves in --output_dir: checkpoints/<step>, and `last` linking to the newest."""
    checkpoint = run / "checkpoints" / f"{step:06d}"
    (checkpoint / "training_state").mkdir(parents=True)
    (checkpoint / "pretrained_model").mkdir()
    (checkpoint / "training_state" / "training_step.json").write_text(json.dumps({"step": step}))
    saved = {"steps": steps, "batch_size": 16, "policy": {"type": "act"}, "dataset": {"root": root}}
    (checkpoint / "pretrained_model" / "train_config.json").write_text(json.dumps(saved))
    (run / LAST).symlink_to(checkpoint.name)
    return run


def test_a_rerun_continues_its_run_and_refuses_other_settings(tmp_path, monkeypatch, capsys):
    """lerobot-train refuses an existing --output_dir, and its own resume trains only to the steps the run
    was first given: `make lerobot LEROBOT_STEPS=4000` after 2000 trained nothing, then evaluated the old
    model."""
    monkeypatch.chdir(tmp_path)
    here = tmp_path.resolve()  # the paths compared are resolved
    args = ["--policy.type=act", "--dataset.root=data/lerobot", "--batch_size=16", "--output_dir=run"]
    assert continued([*args, "--steps=2000"]) == [*args, "--steps=2000"]  # a new run
    trained_run(tmp_path / "run", 2000, 2000)
    assert continued([*args, "--steps=2000"]) is None
    assert "run: trained 2000 steps already" in capsys.readouterr().out
    assert continued([*args, "--steps", "4000"]) == [
        "--resume=true",
        f"--config_path={Path('run', LAST, 'pretrained_model', 'train_config.json')}",
        "--steps=4000",
    ]
    for other, named in (
        ("--steps=1000", "--steps: 2000 trained, 1000 asked (only --steps may grow)"),
        ("--policy.type=diffusion", "--policy.type: act -> diffusion"),
        (
            "--dataset.root=data64/lerobot",
            f"--dataset.root: {here / 'data/lerobot'} -> {here / 'data64/lerobot'}",
        ),
        ("--batch_size=8", "--batch_size: 16 -> 8"),
    ):
        with pytest.raises(
            ConfigMismatchError, match=re.escape(f"run was trained with other settings ({named});")
        ):
            continued([*args, "--steps=2000", other])
    assert continued([*args, "--resume=true"]) == [*args, "--resume=true"]  # LeRobot's own resume, as given


def test_a_run_killed_before_its_first_checkpoint_starts_again_and_other_directories_are_kept(tmp_path):
    half_saved = tmp_path / "run" / "checkpoints" / "000500"
    half_saved.mkdir(parents=True)
    args = ["--policy.type=act", f"--output_dir={tmp_path / 'run'}", "--steps=2000"]
    assert continued(args) == args and not (tmp_path / "run").exists()
    (tmp_path / "notes").mkdir()
    (tmp_path / "notes" / "todo.txt").write_text("mine")
    # a run whose `last` link is gone (killed while lerobot-train relinked it) keeps its checkpoints
    trained_run(tmp_path / "unlinked", 500, 2000)
    (tmp_path / "unlinked" / LAST).unlink()
    for kept in ("notes", "unlinked"):
        with pytest.raises(
            OutputExistsError, match=f"{kept} exists without a LeRobot run's checkpoints/last"
        ):
            continued(["--policy.type=act", f"--output_dir={tmp_path / kept}"])
    assert (tmp_path / "notes" / "todo.txt").exists() and (
        tmp_path / "unlinked" / "checkpoints" / "000500"
    ).exists()


def test_the_cpu_preset_adds_the_policy_types_settings_and_flags_given_replace_them():
    act = with_preset(["--preset=cpu", "--policy.type=act", "--policy.chunk_size=8", "--steps", "3"])
    assert act[: len(RUN_FLAGS)] == RUN_FLAGS and act[-4:] == [
        "--policy.type=act",
        "--policy.chunk_size=8",
        "--steps",
        "3",
    ]
    assert "--policy.pretrained_backbone_weights=null" in act and "--policy.n_action_steps=16" in act
    assert [a for a in act if a.startswith("--policy.chunk_size")] == ["--policy.chunk_size=8"]  # once: ours
    smolvla = with_preset(["--policy.type", "smolvla", "--preset=cpu"])
    assert f"--policy.vlm_model_name={SMOLVLM_DIR.resolve()}" in smolvla and "--preset=cpu" not in smolvla
    assert with_preset(["--policy.type=act"]) == ["--policy.type=act"]  # no preset: LeRobot's own settings
    with pytest.raises(InputError, match="--preset=gpu: choose among cpu"):
        with_preset(["--preset=gpu", "--policy.type=act"])
    with pytest.raises(
        InputError, match="--preset=cpu needs --policy.type among act, diffusion, smolvla .given: pi0"
    ):
        with_preset(["--preset=cpu", "--policy.type=pi0"])


def test_only_the_checkpoint_last_links_to_is_kept(tmp_path):
    run = trained_run(tmp_path / "run", 1000, 2000)
    assert trained_step(run) == 1000 and trained_step(tmp_path / "none") == 0
    (run / "checkpoints" / "000500" / "pretrained_model").mkdir(parents=True)  # an older one
    (run / "checkpoints" / "001500" / "pretrained_model").mkdir(parents=True)  # a save the deadline cut off
    keep_last_checkpoint(run)
    assert sorted(p.name for p in (run / "checkpoints").iterdir()) == ["001000", "last"]
    assert trained_step(run) == 1000

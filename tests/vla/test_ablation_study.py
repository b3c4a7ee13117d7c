"""The ablation study as one resumable command: rows trained and evaluated in order within a time budget,
then the paper's tables."""

import shutil
import sys

import pytest

from mobilemani_rl.utils.errors import InputError, MissingFileError
from mobilemani_vla import ablation_study
from mobilemani_vla.data.synthetic import write_synthetic_dataset
from mobilemani_vla.eval.results import finished, read_records

SPLIT_FILES = {
    "unseen_unseen": "test_objects_test_scenes",
    "seen_seen": "train_objects_train_scenes",
    "seen_unseen": "train_objects_test_scenes",
    "unseen_seen": "test_objects_train_scenes",
}


def tiny_evaluation(tmp_path) -> list[str]:
    """The first laptop object of each object split (opened), 8-step episodes."""
    return [
        "subset.categories=[laptop]",
        "subset.skills=[open]",
        "subset.objects_per_category=1",
        "env.episode_length=8",
        f"output_dir={tmp_path}/eval",
    ]


def run_study(monkeypatch, tmp_path, *extra: str) -> None:
    """Two rows with the tiny model on a synthetic dataset, each split evaluated on the first laptop object
    of its object split (opened), one 8-step episode per combination."""
    data = tmp_path / "data"
    if not data.exists():
        write_synthetic_dataset(data, episodes=2, length=20)
    train = [
        "vla/model=tiny",
        "vla/train=cpu",
        f"data.root={data}",
        "data.repo_id=synthetic/g1",
        "data.heldout_episodes=1",
        f"train.output_dir={tmp_path}/vla/${{name}}",
        "train.logger=none",
        "train.progress=false",
        "train.batch_size=2",
        "train.steps=2",
        "train.diagnose_every=0",
    ]
    evaluation = tiny_evaluation(tmp_path)
    argv = ["ablation_study", "--scale", "paper", "--rows", "ablation_image_all", "ablation_image_head_rgb"]
    argv += ["--episodes", "1", "--workers", "1", "--tables", str(tmp_path / "tables"), *extra]
    monkeypatch.setattr(sys, "argv", [*argv, "--train", *train, "--eval", *evaluation])
    ablation_study.main()


def test_the_study_trains_and_evaluates_its_rows_in_order_and_a_rerun_has_nothing_left(
    tmp_path, monkeypatch, capsys
):
    # Too few minutes for a training piece: nothing trains, the tables still show what there is.
    run_study(monkeypatch, tmp_path, "--minutes", "1")
    out = capsys.readouterr().out
    assert "== " not in out and "--minutes 1 spent: the same command continues the study" in out
    assert not (tmp_path / "vla").exists() and (tmp_path / "tables" / "vla_ablation_image.md").is_file()

    run_study(monkeypatch, tmp_path, "--minutes", "60")
    out = capsys.readouterr().out
    # the order of the work, each training piece's minutes (what the budget leaves) cut off
    order = [line.split(" (this piece")[0] for line in out.splitlines() if line.startswith("== ")]
    assert order == [
        "== ablation_image_all: training to step 2",
        "== ablation_image_all: evaluating on test_objects_test_scenes",
        "== ablation_image_head_rgb: training to step 2",
        "== ablation_image_head_rgb: evaluating on test_objects_test_scenes",
        "== ablation_image_all: evaluating on train_objects_train_scenes",
        "== ablation_image_all: evaluating on train_objects_test_scenes",
        "== ablation_image_all: evaluating on test_objects_train_scenes",
    ]
    assert "the study's rows ablation_image_all, ablation_image_head_rgb are trained and evaluated" in out
    # Each split file complete: seen objects in one room of their split, unseen objects in the four test rooms
    # or the first four training rooms.
    episodes = {"unseen_unseen": 4, "seen_seen": 1, "seen_unseen": 1, "unseen_seen": 4}
    for split, count in episodes.items():
        path = tmp_path / "eval" / "g1" / "ablation_image_all" / f"{SPLIT_FILES[split]}.jsonl"
        records = read_records(path)
        assert len(records) == count and finished(path, records), split
    seen = read_records(tmp_path / "eval/g1/ablation_image_all/train_objects_train_scenes.jsonl")
    assert [(r["object_id"], r["scene"]) for r in seen] == [("laptop/0000", seen[0]["scene"])]
    image = (tmp_path / "tables" / "vla_ablation_image.md").read_text()
    assert "Our runs: g1/ablation_image_all: tiny model, 2 steps x 2 = 4 samples" in image
    assert "g1/ablation_image_head_rgb: tiny model" in image and "| 4 | 7.9 |" in image

    run_study(monkeypatch, tmp_path, "--minutes", "60")  # everything done: nothing trains or runs again
    out = capsys.readouterr().out
    assert "== " not in out and "are trained and evaluated" in out


def test_a_missing_dataset_is_named_before_anything_runs(tmp_path, monkeypatch):
    tables = tmp_path / "tables"
    argv = ["ablation_study", "--tables", str(tables), "--train", f"data.root={tmp_path / 'none'}"]
    monkeypatch.setattr(sys, "argv", argv)
    with pytest.raises(
        MissingFileError, match=f"no ablation dataset at {tmp_path / 'none'} .data.root.: make it"
    ):
        ablation_study.main.__wrapped__()
    assert not tables.exists() and list(tmp_path.iterdir()) == []


def test_an_unknown_row_is_named_before_anything_runs(tmp_path, monkeypatch):
    tables = tmp_path / "tables"
    monkeypatch.setattr(sys, "argv", ["ablation_study", "--rows", "ablation_depth", "--tables", str(tables)])
    with pytest.raises(InputError, match="--rows: unknown ablation_depth; choose among ablation_image_all, "):
        ablation_study.main.__wrapped__()
    assert not tables.exists()
    # an evaluation override is checked with the rest, not hours later when the first evaluation starts
    argv = ["ablation_study", "--tables", str(tables), "--train", f"data.root={tmp_path / 'none'}"]
    monkeypatch.setattr(sys, "argv", [*argv, "--eval", "episodes_per_batch=0"])
    with pytest.raises(InputError, match="episodes_per_batch"):
        ablation_study.main.__wrapped__()
    assert list(tmp_path.iterdir()) == []


def test_a_baseline_trains_with_lerobot_and_joins_the_model_table(tmp_path, monkeypatch, capsys):
    """ACT at test size through lerobot-train (the cpu preset) on the study's dataset, then the same
    evaluation as the VLA rows."""
    data = write_synthetic_dataset(tmp_path / "data", episodes=2, length=20)
    tiny_act = [
        *("policy.dim_model=32", "policy.n_heads=2", "policy.dim_feedforward=64"),
        *("policy.n_encoder_layers=1", "policy.n_decoder_layers=1", "policy.latent_dim=8"),
        *("batch_size=2", "steps=3", "log_freq=1"),
    ]
    evaluation = tiny_evaluation(tmp_path)
    argv = ["ablation_study", "--rows", "ablation_act", "--episodes", "1", "--workers", "1"]
    argv += ["--tables", str(tmp_path / "tables"), "--lerobot-out", str(tmp_path / "lerobot")]
    argv += ["--train", f"data.root={data}", "data.repo_id=synthetic/g1", "--eval", *evaluation]
    monkeypatch.setattr(sys, "argv", [*argv, "--lerobot", *tiny_act])
    ablation_study.main()
    out = capsys.readouterr().out
    assert "== ablation_act: training to step 3 from step 0" in out
    assert "== ablation_act: evaluating on test_objects_test_scenes" in out
    # saved at every step (3 // 60 steps, at least 1), only the last checkpoint kept
    run = tmp_path / "lerobot" / "ablation_act"
    assert sorted(p.name for p in (run / "checkpoints").iterdir()) == ["000003", "last"]
    config = (run / "checkpoints" / "000003" / "pretrained_model" / "config.json").read_text()
    assert '"pretrained_backbone_weights": null' in config and '"chunk_size": 16' in config  # the cpu preset
    path = tmp_path / "eval" / "g1" / "ablation_act" / "test_objects_test_scenes.jsonl"
    assert len(read_records(path)) == 4 and finished(path, read_records(path))
    models = (tmp_path / "tables" / "vla_models.md").read_text()
    assert "| ACT | " in models and "g1/ablation_act: act model, 3 steps x 2 = 6 samples" in models

    ablation_study.main()  # done: nothing trains or runs again
    assert "== " not in capsys.readouterr().out


def test_a_row_with_recorded_evaluations_is_not_trained_again(tmp_path, monkeypatch, capsys):
    run_study(monkeypatch, tmp_path, "--minutes", "60")
    capsys.readouterr()
    # The evaluations kept, checkpoints gone, no dataset at data.root (a clone with the results): nothing
    # to train, nothing asks for the dataset, and the tables are written again from the records.
    shutil.rmtree(tmp_path / "vla")
    shutil.rmtree(tmp_path / "tables")
    argv = ["ablation_study", "--scale", "paper", "--rows", "ablation_image_all", "ablation_image_head_rgb"]
    argv += ["--episodes", "1", "--workers", "1", "--tables", str(tmp_path / "tables")]
    argv += ["--train", f"data.root={tmp_path / 'none'}", "--eval", *tiny_evaluation(tmp_path)]
    monkeypatch.setattr(sys, "argv", argv)
    ablation_study.main()
    out = capsys.readouterr().out
    assert "== " not in out and "are trained and evaluated" in out
    assert (
        "g1/ablation_image_head_rgb: tiny model"
        in (tmp_path / "tables" / "vla_ablation_image.md").read_text()
    )
    # A split that lacks its records trains its row again, and only that row.
    for name in ("test_objects_train_scenes.jsonl", "test_objects_train_scenes.summary.json"):
        (tmp_path / "eval/g1/ablation_image_all" / name).unlink()
    run_study(monkeypatch, tmp_path, "--minutes", "60")
    out = capsys.readouterr().out
    assert [line.split(" (this piece")[0] for line in out.splitlines() if line.startswith("== ")] == [
        "== ablation_image_all: training to step 2",
        "== ablation_image_all: evaluating on test_objects_train_scenes",
    ]
    assert not (tmp_path / "vla" / "ablation_image_head_rgb").exists()

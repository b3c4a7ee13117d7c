"""The paper's VLA tables and bar plots from evaluation results files."""

import json
from pathlib import Path

import pytest

from mobilemani_rl.utils.stats import mcnemar_p, two_proportion_p
from mobilemani_vla.eval import tables as vla_tables
from mobilemani_vla.eval.results import read_records, summarize, summary_path
from mobilemani_vla.eval.tables import PROTOCOL_SPLIT, bar_plots, build_tables, load


def write_run(
    root: Path,
    robot: str,
    run: str,
    split: str,
    outcomes: dict[tuple[str, str, str], list[bool]],
    finished: bool = True,
) -> Path:
    """A results file as `make eval` writes it, with the summary it writes last when `finished`."""
    path = root / robot / run / f"{split}.jsonl"
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [
        json.dumps(
            {
                "robot": robot,
                "object_id": obj,
                "category": obj.split("/")[0],
                "skill": skill,
                "scene": scene,
                "episode": e,
                "success": ok,
            }
        )
        for (obj, skill, scene), results in outcomes.items()
        for e, ok in enumerate(results)
    ]
    path.write_text("\n".join(lines) + "\n")
    if finished:
        summary_path(path).write_text(json.dumps(summarize(read_records(path))))
    return path


def test_tables_and_plots_from_results(tmp_path):
    root = tmp_path / "eval"
    # box/0010 open: 3/4; box/0011 open: 1/4 -> box open/pull/pick = mean over objects = 50%.
    write_run(
        root,
        "g1",
        "default",
        PROTOCOL_SPLIT,
        {
            ("box/0010", "open", "tabletop/16"): [True, True, True, False],
            ("box/0011", "open", "tabletop/17"): [True, False, False, False],
            ("box/0010", "close", "tabletop/16"): [True, True, True, True],
            ("cart/0012", "pull", "space/16"): [False, False],
        },
    )
    write_run(root, "xhand", "default", PROTOCOL_SPLIT, {("box/0010", "close", "tabletop/16"): [False, True]})
    for split, rate in (("train_objects_train_scenes", [True, True]), (PROTOCOL_SPLIT, [True, False])):
        write_run(root, "g1", "ablation_image_all", split, {("laptop/0030", "open", "tabletop/16"): rate})
    write_run(root, "g1", "lerobot_act", PROTOCOL_SPLIT, {("laptop/0030", "open", "tabletop/16"): [False]})
    write_run(
        root,
        "g1",
        "ablation_image_head_rgbd",
        PROTOCOL_SPLIT,
        {("laptop/0030", "open", "tabletop/16"): [True]},
    )
    results = load(root)
    tables = build_tables(results, "default", "ablation_image_all")

    skill = tables["vla_by_skill"].markdown()
    assert "| Open | 50.0 | - | 42.9 | 34.5 |" in skill
    assert "| Close | 100.0 | 50.0 | 75.8 | 77.5 |" in skill
    assert "| Pull | 0.0 | - | 34.4 | 29.4 |" in skill
    category = tables["vla_by_category"].markdown()
    assert "| Box | 4 | 50.0 | - | 100.0 | 50.0 | 55.0 | 22.5 | 61.9 | 95.0 |" in category
    assert "| Holistic | 18 | - | - | - | - | 28.8 | 40.2 | - | - |" in category
    image = tables["vla_ablation_image"].markdown()
    assert (
        "| x | x | x | x | x |  |  | 50.0 | 9.5-90.5 | 2 | 28.2 |" in image
        and "| x |  |  |  | x |  |  | - | - | - | 7.9 |" in image
        and "| x | x |  |  | x |  |  | 100.0 | 20.7-100.0 | 1 | 14.1 |" in image
    )
    # cameras all on
    assert "|  |  |  |  |  |  |  | - | - | - | 22.4 |" not in tables["vla_ablation_state"].markdown()
    splits = tables["vla_seen_unseen"].markdown()
    assert (
        "| seen objects, seen scenes | 100.0 | 34.2-100.0 | 2 | 59.6 |" in splits
        and "| seen objects, unseen scenes | - | - | - | 51.3 |" in splits
    )
    models = tables["vla_models"].markdown()
    assert "| MobileManiVLA | 50.0 | 9.5-90.5 | 2 | 28.2 |" in models
    assert "| lerobot_act | 0.0 | 0.0-79.3 | 1 | - |" in models
    assert "ablation_image_head_rgbd" not in models  # an ablation row, in the image table instead
    latex = tables["vla_by_skill"].latex()
    assert r"\toprule" in latex and "Open & 50.0 & - & 42.9 & 34.5" in latex

    paths = bar_plots(results, "default", tmp_path)
    assert [p.name for p in paths] == ["vla_by_category.png", "vla_by_skill.png"]
    assert all(p.stat().st_size > 10_000 for p in paths)


def test_captions_state_the_training_scale_each_evaluation_recorded(tmp_path):
    """A table's caption states how much training each trained run it shows holds, as its evaluation wrote it
    to the run's config.json; untrained policies (scripted, teachers) record none and are not named."""
    root = tmp_path / "eval"
    outcomes = {("laptop/0030", "open", "tabletop/16"): [True, False]}
    for run, training in (
        (
            "ablation_image_all",
            {
                "model": "cpu",
                "steps": 30000,
                "batch_size": 32,
                "samples": 960000,
                "train_episodes": 4326,
                "image_size": [64, 64],
                "dataset_sha256": "3f2a9c1e" + "0" * 56,
            },
        ),
        ("lerobot_act", {"model": "act", "steps": 5000, "batch_size": 8, "samples": 40000}),
        ("scripted", {}),
    ):
        write_run(root, "g1", run, PROTOCOL_SPLIT, outcomes)
        (root / "g1" / run / "config.json").write_text(json.dumps({"policy_training": training}))
    tables = build_tables(load(root), "default", "ablation_image_all")
    main = (
        "g1/ablation_image_all: cpu model, 30,000 steps x 32 = 960,000 samples, from 4,326 episodes "
        "(dataset 3f2a9c1e), at 64 px"
    )
    assert tables["vla_ablation_image"].caption.endswith(f"Our runs: {main}.")
    models = tables["vla_models"].caption
    assert main in models and "g1/lerobot_act: act model, 5,000 steps x 8 = 40,000 samples" in models
    assert "scripted:" not in models and "Our runs" not in tables["vla_by_skill"].caption


def test_tables_name_the_results_they_miss(tmp_path, monkeypatch, capsys):
    """Results under another run name than --main: every table still prints,
    and the missing files are named."""
    root = tmp_path / "eval"
    write_run(root, "g1", "vla_open", PROTOCOL_SPLIT, {("box/0010", "open", "tabletop/16"): [True, False]})
    monkeypatch.setattr(
        "sys.argv", ["tables", str(root), "--out", str(tmp_path / "out"), "--main", "default"]
    )
    vla_tables.main()
    out = capsys.readouterr().out
    assert (
        f"results under {root}: g1/vla_open/{PROTOCOL_SPLIT}" in out
        and "| vla_open | 50.0 | 9.5-90.5 | 2 | - |" in out
    )
    missing = out.split("missing inputs")[1]
    assert f"{root}/g1/default/{PROTOCOL_SPLIT}.jsonl" in missing
    assert f"{root}/xhand/default/{PROTOCOL_SPLIT}.jsonl" in missing
    assert f"{root}/g1/ablation_image_all/train_objects_train_scenes.jsonl" in missing
    assert "vla_open" not in missing


def test_tables_mark_what_they_count_from_unfinished_evaluations(tmp_path, monkeypatch, capsys):
    """`make tables` beside a running or stopped `make eval`: its cells count the episodes so far, and say
    so."""
    root = tmp_path / "eval"
    outcomes = {("box/0010", "open", "tabletop/16"): [True, False, False]}
    running = write_run(root, "g1", "default", PROTOCOL_SPLIT, outcomes, finished=False)
    write_run(root, "xhand", "default", PROTOCOL_SPLIT, outcomes)
    write_run(root, "g1", "lerobot_act", PROTOCOL_SPLIT, outcomes)
    tables = build_tables(load(root), "default", "ablation_image_all")
    note = f"Unfinished evaluations: g1/default/{PROTOCOL_SPLIT} (3 episodes so far).**"
    assert "| Open | 33.3 | 33.3 |" in tables["vla_by_skill"].markdown()
    assert note in tables["vla_by_skill"].markdown() and note in tables["vla_by_category"].markdown()
    assert note in tables["vla_models"].markdown()  # default's row among the other runs
    assert "Unfinished" not in tables["vla_seen_unseen"].markdown()  # ablation_image_all's, not default's
    # a finished run that a later, larger protocol is growing: its summary counts fewer episodes
    summary_path(running).write_text(json.dumps(summarize(read_records(running)[:2])))
    assert "Unfinished" in build_tables(load(root), "default", "x")["vla_by_skill"].caption
    monkeypatch.setattr("sys.argv", ["tables", str(root), "--out", str(tmp_path / "out")])
    vla_tables.main()
    out = capsys.readouterr().out
    assert (
        "unfinished evaluations (still running or stopped; rerun `make eval` to finish): g1/default/" in out
    )


def test_takeaway_tests_pair_shared_episodes_and_compare_different_ones_unpaired(tmp_path):
    root = tmp_path / "eval"
    key = ("laptop/0030", "open", "tabletop/16")
    # The same 10 episodes: the depth row wins 4 that head RGB loses, head RGB 1 that the depth row loses.
    write_run(root, "g1", "ablation_image_head_rgb", PROTOCOL_SPLIT, {key: [True] + [False] * 9})
    write_run(
        root, "g1", "ablation_image_head_rgbd", PROTOCOL_SPLIT, {key: [False] + [True] * 4 + [False] * 5}
    )
    # Seen objects in unseen rooms up from seen rooms here: against the paper's direction.
    write_run(root, "g1", "ablation_image_all", "train_objects_train_scenes", {key: [True] * 2 + [False] * 8})
    unseen_room = ("laptop/0030", "open", "tabletop/17")
    write_run(
        root, "g1", "ablation_image_all", "train_objects_test_scenes", {unseen_room: [True] * 8 + [False] * 2}
    )
    rows = {
        row[1]: row for row in build_tables(load(root), "default", "ablation_image_all")["vla_takeaways"].rows
    }

    depth = rows["head RGB, then + head depth"]
    assert depth[2:5] == ["10.0 (1/10)", "40.0 (4/10)", "+30.0"]
    assert depth[5] == "paired, 10 episodes: 1 vs 4 won by one only"
    assert depth[6] == f"{2 * 6 / 32:.3f}"  # P(at most 1 of 5 discordant on one side) x 2
    assert depth[7:] == ["7.9", "14.1", "yes"]
    rooms = rows["seen objects and scenes, then unseen scenes"]
    assert rooms[2:6] == ["20.0 (2/10)", "80.0 (8/10)", "+60.0", "unpaired (different episodes)"]
    assert rooms[7:] == ["59.6", "51.3", "no"]
    assert rows["no state, then + wrist pose"][2:7] == ["-"] * 5


def test_significance_tests_of_success_rates():
    assert mcnemar_p(16, 35) == mcnemar_p(35, 16) == pytest.approx(0.011, abs=5e-4)
    assert mcnemar_p(1, 4) == 2 * (1 + 5) / 2**5
    assert mcnemar_p(0, 0) == mcnemar_p(3, 3) == 1.0
    # 183/544 against 150/528: z = 1.85
    assert two_proportion_p(183, 544, 150, 528) == pytest.approx(0.064, abs=1e-3)
    assert two_proportion_p(5, 10, 10, 20) == 1.0
    assert two_proportion_p(0, 10, 0, 20) == 1.0

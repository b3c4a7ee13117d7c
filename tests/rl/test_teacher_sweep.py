"""The teacher sweep: every category-skill row, resumable, with per-row and paper tables on test objects."""

import json
import shutil

import pytest

from mobilemani_rl.rl import sweep as teacher_sweep
from mobilemani_rl.utils.errors import ConfigMismatchError, InputError

TINY = ["rl/ppo=tiny", "objects_per_policy=1", "eval_episodes=1"]


def test_g1_has_the_papers_39_rows():
    rows = teacher_sweep.rows()
    assert len(rows) == 39 and len(set(rows)) == 39
    assert ("cart", "pull") in rows and ("holistic", "pick") in rows and ("box", "close") in rows
    assert teacher_sweep.rows(["cart", "box"], ["open", "push"]) == [("cart", "push"), ("box", "open")]


def test_a_row_trains_evaluates_on_test_objects_and_is_skipped_when_done(tmp_path, capsys):
    runs, out = tmp_path / "runs", tmp_path / "out"
    args = ["--runs", str(runs), "--out", str(out), *TINY, "--categories", "microwave", "--skills", "open"]
    teacher_sweep.main(args)
    records = json.loads((out / "teachers_g1.json").read_text())
    assert [(r["category"], r["skill"]) for r in records] == [("microwave", "open")]
    row = records[0]
    assert row["test_objects"] == 2 and row["trained_objects"] == 1  # microwave: 3 train, 2 test objects
    assert 0.0 <= row["test_success"] <= 1.0 and row["samples"] == 3 * 8 * 8  # tiny: 3 iterations x 8 x 8
    assert row["wall_minutes"] is not None and "task.object=microwave" in row["command"]
    assert "1 of 39 rows finished" in (out / "teachers_g1.md").read_text()
    by_skill = (out / "rl_by_skill.md").read_text()
    assert "| Open |" in by_skill and "86.6" in by_skill  # ours beside the paper's
    assert (out / "rl_by_skill.tex").is_file() and (out / "rl_by_category.tex").is_file()
    run_dir = runs / "g1" / "microwave" / "open"
    before = {p.name: p.stat().st_mtime for p in run_dir.iterdir()}
    # rerun, the overrides after the names: the finished row is not trained or evaluated again
    names_first = ["--runs", str(runs), "--out", str(out), "--categories", "microwave", "--skills", "open"]
    teacher_sweep.main([*names_first, *TINY])
    assert {p.name: p.stat().st_mtime for p in run_dir.iterdir()} == before
    assert json.loads((out / "teachers_g1.json").read_text()) == records
    # another row, trained under other runs: the files keep the first one, the paper tables too
    teacher_sweep.main(["--runs", str(tmp_path / "other_runs"), *args[2:-1], "close"])
    rows = [(r["category"], r["skill"]) for r in json.loads((out / "teachers_g1.json").read_text())]
    assert rows == [("microwave", "open"), ("microwave", "close")]
    assert "2 of 39 rows finished" in (out / "teachers_g1.md").read_text()
    by_skill = (out / "rl_by_skill.md").read_text()
    assert "| Open | - |" not in by_skill and "| Close | - |" not in by_skill


def test_sweeps_into_robot_named_folders_write_both_robots_paper_tables_one_level_up(tmp_path):
    """`make teachers` writes to TEACHERS_OUT/<robot>: each robot's sweep leaves the two-robot tables in
    TEACHERS_OUT, from every robot's records, whichever robot ran last."""
    runs, root = tmp_path / "runs", tmp_path / "tables"
    row = [*TINY, "--categories", "microwave", "--skills", "open"]
    for robot in ("g1", "xhand"):
        teacher_sweep.main(["--robot", robot, "--runs", str(runs), "--out", str(root / robot), *row])
    both = (root / "rl_by_skill.md").read_text()
    open_row = next(line for line in both.splitlines() if line.startswith("| Open"))
    assert " - " not in open_row  # G1 and XHand both measured, beside the paper's two
    assert "G1 1 of 39, XHand 1 of 39 rows" in both
    # each robot's own folder keeps its own column only
    assert "| Open | - |" in (root / "xhand" / "rl_by_skill.md").read_text()


def test_a_row_recorded_by_the_same_command_is_kept_when_its_runs_are_gone(tmp_path):
    """Rows finished on another machine (their checkpoints not kept) are not trained again; a row recorded by
    another command is."""
    runs, out = tmp_path / "runs", tmp_path / "out"
    args = ["--runs", str(runs), "--out", str(out), *TINY, "--categories", "microwave", "--skills", "open"]
    teacher_sweep.main(args)
    records = json.loads((out / "teachers_g1.json").read_text())
    shutil.rmtree(runs)
    teacher_sweep.main(args)
    assert not runs.exists() and json.loads((out / "teachers_g1.json").read_text()) == records
    teacher_sweep.main([*args, "eval_episodes=2"])  # another command: trained and recorded anew
    rerun = json.loads((out / "teachers_g1.json").read_text())
    assert (runs / "g1" / "microwave" / "open").is_dir() and "eval_episodes=2" in rerun[0]["command"]


def test_a_finished_row_goes_on_to_its_skills_iterations_and_refuses_other_settings(tmp_path):
    runs, out = tmp_path / "runs", tmp_path / "out"
    args = ["--runs", str(runs), "--out", str(out), *TINY, "--categories", "microwave", "--skills", "open"]
    teacher_sweep.main(args)  # tiny: 3 iterations
    run_dir = runs / "g1" / "microwave" / "open"
    before = {p.name: p.stat().st_mtime for p in run_dir.iterdir()}
    # more iterations with another setting: refused for the setting before the row goes on
    with pytest.raises(ConfigMismatchError, match=r"rl.ppo.learning_rate: .* -> 0.5"):
        teacher_sweep.main([*args, "rl.ppo.learning_rate=0.5", "--skill-iterations", "open:4"])
    assert {p.name: p.stat().st_mtime for p in run_dir.iterdir()} == before
    teacher_sweep.main([*args, "--skill-iterations", "open:4", "pick:9"])
    [row] = json.loads((out / "teachers_g1.json").read_text())
    assert row["samples"] == 4 * 8 * 8 and row["command"].endswith("rl.ppo.max_iterations=4")
    assert (run_dir / "eval_model_3_1000.json").is_file()  # the row's final checkpoint, evaluated


def test_a_skills_own_iterations_replace_the_sweeps_and_bad_ones_name_the_option(tmp_path):
    common = ["rl.ppo.max_iterations=300", "rl.ppo.warm_start.episodes=128"]
    row = teacher_sweep.row_overrides("g1", "holistic", "pick", tmp_path, common, iterations=3000)
    assert row[-2:] == ["rl.ppo.warm_start.episodes=128", "rl.ppo.max_iterations=3000"]
    assert "rl.ppo.max_iterations=300" not in row
    assert teacher_sweep.skill_iterations("pick:3000") == ("pick", 3000)
    with pytest.raises(InputError, match="unknown --skill-iterations skill 'pik'"):
        teacher_sweep.main(["--runs", str(tmp_path), "--skill-iterations", "pik:3000"])
    for bad in ("pick", "pick:0", "pick:many"):
        with pytest.raises(InputError, match=f"--skill-iterations {bad}: expected SKILL:N with N >= 1"):
            teacher_sweep.main(["--runs", str(tmp_path), "--skill-iterations", bad])
    assert not any(tmp_path.iterdir())


def record(test: float, train: float, scripted: float | None, objects: dict[str, float]) -> dict:
    return {
        "robot": "g1",
        "category": "box",
        "skill": "open",
        "test_success": test,
        "train_success": train,
        "scripted_success": scripted,
        "test_object_success": objects,
        "test_objects": 4,
        "trained_objects": 8,
        "samples": 1,
        "wall_minutes": 1.0,
    }


def test_rows_below_the_papers_skill_mean_name_the_stage_they_fall_short_in():
    assert "0.80" not in teacher_sweep.diagnosis(record(0.5, 0.9, 0.8, {}))  # percentages, not fractions
    objects = {"box/0010": 0.9, "box/0011": 0.2, "box/0012": 0.4}
    in_training = teacher_sweep.diagnosis(record(0.5, 0.6, 0.4, objects))  # the paper's G1 open: 86.6%
    assert "PPO took the trained objects from the scripted demonstrations' 40.0% to 60.0%" in in_training
    assert in_training.endswith("weakest test objects: box/0011 20.0%, box/0012 40.0%")
    unseen_only = teacher_sweep.diagnosis(record(0.5, 0.9, 0.95, objects))
    assert unseen_only.startswith(
        "the trained objects reach the paper's mean (90.0%), the test objects do not"
    )
    assert "60.0% (trained from scratch)" in teacher_sweep.diagnosis(record(0.5, 0.6, None, {}))
    above = {**record(0.97, 0.97, 1.0, {}), "skill": "close"}  # the paper's G1 close: 96.2%
    text = teacher_sweep.rows_markdown([record(0.5, 0.6, None, {}), above], 39)
    assert "Rows below the paper's mean for their skill (1):" in text and "- box open: 50.0% vs" in text


def test_bad_rows_and_missing_evaluation_are_refused_before_training(tmp_path):
    with pytest.raises(InputError, match="unknown category 'microwav'"):
        teacher_sweep.main(["--runs", str(tmp_path), "--categories", "microwav"])
    with pytest.raises(
        InputError, match="--skills pick selects no row of --categories box cart, whose skills are"
    ):
        teacher_sweep.main(["--runs", str(tmp_path), "--categories", "box", "cart", "--skills", "pick"])
    with pytest.raises(InputError, match="eval_episodes must be >= 1"):
        teacher_sweep.main(["--runs", str(tmp_path), "rl/ppo=tiny", "eval_episodes=0"])
    assert not any(tmp_path.iterdir())


def test_test_episodes_raise_the_episodes_per_object_of_categories_with_few_test_objects(tmp_path):
    def episodes(category: str, **kwargs) -> list[str]:
        row = teacher_sweep.row_overrides("g1", category, "open", tmp_path, [], **kwargs)
        return [o for o in row if o.startswith("eval_episodes=")]

    assert episodes("cabinet", test_episodes=256) == ["eval_episodes=128"]  # 2 test objects
    assert episodes("faucet", test_episodes=256) == ["eval_episodes=64"]  # 18 test objects: the default
    assert episodes("cabinet") == ["eval_episodes=64"]
    with pytest.raises(InputError, match="--test-episodes -1: expected N >= 0"):
        teacher_sweep.main(["--runs", str(tmp_path), "--test-episodes", "-1"])

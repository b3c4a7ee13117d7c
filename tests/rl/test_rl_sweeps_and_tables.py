"""Sweep launcher configs compose, and evaluation files become the paper-style tables."""

import json
import subprocess
import sys

import pytest
from checkout import ROOT, checkout_env
from hydra import compose, initialize_config_dir

from mobilemani_rl.rl import tables as teacher_tables
from mobilemani_rl.utils.table_format import Table


def test_slurm_launcher_config_composes():
    with initialize_config_dir(config_dir=str(ROOT / "conf"), version_base="1.3"):
        cfg = compose(config_name="rl", overrides=["hydra/launcher=slurm"], return_hydra_config=True)
    launcher = cfg.hydra.launcher
    assert launcher._target_.endswith("SlurmLauncher")
    assert launcher.cpus_per_task == 16 and launcher.timeout_min == 240


@pytest.mark.slow
def test_a_sweep_through_submitit_trains_one_run_per_job(tmp_path):
    """The sweep line of docs/usage.md (Scaling out) on submitit's local executor, the plugin the slurm
    launcher extends: each job pickles the task, trains in its own run directory and reports its result
    back (no cluster needed)."""
    command = [
        sys.executable,
        "-m",
        "mobilemani_rl.rl.train",
        "-m",
        "hydra/launcher=submitit_local",
        "task.object=box/0000,box/0001",
        "task.skill=open",
        "rl/ppo=tiny",
    ]
    env = checkout_env()
    done = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    for obj in ("box/0000", "box/0001"):
        result = json.loads((tmp_path / "outputs/rl/g1" / obj / "open/result.json").read_text())
        assert result["iterations"] == 3 and result["checkpoint"].endswith("model_2.pt")
    (sweep,) = (tmp_path / "outputs/rl/sweeps").iterdir()
    assert sorted(p.name for p in sweep.iterdir() if p.name.isdigit()) == ["0", "1"]


def test_tables_from_evaluation_files(tmp_path, monkeypatch, capsys):
    def write(run: str, robot: str, skill: str, objects: dict[str, float]) -> None:
        run_dir = tmp_path / run
        run_dir.mkdir(parents=True)
        entries = {oid: {"split": "train", "success_rate": rate} for oid, rate in objects.items()}
        (run_dir / "eval_model_9_0.json").write_text(
            json.dumps({"task": {"robot": robot, "object": "x", "skill": skill}, "objects": entries})
        )

    write("a", "g1", "open", {"box/0000": 1.0, "box/0001": 0.5})
    write("b", "xhand", "close", {"laptop/0000": 0.25})
    write("c", "g1", "pick", {"holistic/0020": 0.8})
    monkeypatch.setattr("sys.argv", ["teacher_tables", str(tmp_path), "--out", str(tmp_path / "out")])
    teacher_tables.main()
    by_skill = (tmp_path / "out" / "rl_by_skill.md").read_text()
    assert "| Open | 75.0 | - | 86.6 | 91.9 |" in by_skill
    assert "| Mean | 76.7 | 25.0 | 89.6 | 92.9 |" in by_skill
    assert "(G1 2 of 39, XHand 1 of 39 rows; -: none trained)" in by_skill  # what each mean averages
    by_category = (tmp_path / "out" / "rl_by_category.md").read_text()
    assert "| Box | 14 | 10 | 4 | 75.0 | - | - | - |" in by_category
    assert "| Laptop | 36 | 30 | 6 | - | - | - | 25.0 |" in by_category
    assert "| Holistic | 78 | 60 | 18 | 80.0 | - | - | - |" in by_category
    assert r"\toprule" in (tmp_path / "out" / "rl_by_category.tex").read_text()


def test_tables_without_teacher_evaluations_name_the_missing_input(tmp_path, monkeypatch, capsys):
    """`make tables` with VLA results but no teacher evaluations: the teacher step must not stop it."""
    monkeypatch.setattr("sys.argv", ["teacher_tables", str(tmp_path / "rl"), "--out", str(tmp_path / "out")])
    teacher_tables.main()
    out = capsys.readouterr().out
    assert f"missing input: no teacher evaluation (eval_*.json) under {tmp_path / 'rl'}" in out
    assert "| Open | - | - | 86.6 | 91.9 |" in (tmp_path / "out" / "rl_by_skill.md").read_text()


def test_a_damaged_teacher_evaluation_is_named(tmp_path, monkeypatch, capsys):
    """A cut-short eval_*.json ended `make tables` in json's traceback, naming no file."""
    damaged = tmp_path / "rl" / "g1" / "box" / "open" / "eval_model_9_0.json"
    damaged.parent.mkdir(parents=True)
    damaged.write_text('{"task": {"robot": "g1", ')
    monkeypatch.setattr("sys.argv", ["teacher_tables", str(tmp_path / "rl"), "--out", str(tmp_path / "out")])
    with pytest.raises(SystemExit) as stop:
        teacher_tables.main()
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.startswith(f"error: {damaged} is damaged, not JSON (Expecting")
    assert err.endswith("restore it, or rerun the stage that writes it\n") and not (tmp_path / "out").exists()


def test_latex_escapes_and_rules():
    table = Table(["Object", "Rate"], [["washing_machine", "50%"], ["Mean", "1"]], "A & B", separators=(1,))
    latex = table.latex()
    assert r"washing\_machine & 50\% \\" in latex and r"\midrule" + "\nMean" in latex and r"A \& B" in latex

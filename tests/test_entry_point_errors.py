"""Every command ends bad input with one line, `error: <message>` naming the key, option or file, and exit
status 2, before anything is written; a bug keeps its traceback."""

from pathlib import Path

import pytest
from checkout import ROOT, checkout_env


def test_entry_points_end_bad_input_with_one_line_and_keep_tracebacks_for_bugs(tmp_path, capsys):
    import subprocess
    import sys

    from mobilemani_rl.utils.cli import entry_point
    from mobilemani_rl.utils.errors import InputError

    @entry_point
    def bad() -> None:
        raise InputError("rl.ppo.num_envs=0 must be at least 1")

    with pytest.raises(SystemExit) as stop:
        bad()
    assert stop.value.code == 2 and capsys.readouterr().err == "error: rl.ppo.num_envs=0 must be at least 1\n"
    with pytest.raises(ZeroDivisionError):  # a bug keeps its traceback
        entry_point(lambda: 1 / 0)()
    # As a user runs it: exit 2, one line on stderr, nothing written.
    done = subprocess.run(
        [sys.executable, "-m", "mobilemani_data.collect", "data/subset=tiny", "subset.episodes=-2"]
        + [f"data_dir={tmp_path / 'data'}"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=checkout_env(),
    )
    assert done.returncode == 2
    assert done.stderr == "error: these must be whole numbers of at least 1: subset.episodes=-2\n"
    assert not (tmp_path / "data").exists()


def test_an_output_path_through_a_file_ends_with_one_line_naming_the_file(tmp_path, capsys):
    """`run_dir=`, `data_dir=`, `output_dir=` or `train.output_dir=` naming a file (or a path below one) ended
    in FileExistsError's or NotADirectoryError's traceback when the stage made its folder."""
    import subprocess
    import sys

    from mobilemani_rl.utils.cli import entry_point

    a_file = tmp_path / "notes.txt"
    a_file.write_text("kept")
    for folder in (a_file, a_file / "run"):

        @entry_point
        def make_output(folder: Path = folder) -> None:
            folder.mkdir(parents=True, exist_ok=True)

        with pytest.raises(SystemExit) as stop:
            make_output()
        message = f"error: cannot make the folder {folder}: {a_file} is a file; choose another path\n"
        assert stop.value.code == 2 and capsys.readouterr().err == message

    @entry_point
    def not_about_a_folder() -> None:
        raise FileExistsError("no path")

    with pytest.raises(FileExistsError):  # a bug keeps its traceback
        not_about_a_folder()
    done = subprocess.run(
        [sys.executable, "-m", "mobilemani_data.collect", "data/subset=tiny", f"data_dir={a_file}"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=checkout_env(),
    )
    assert done.returncode == 2 and done.stderr.endswith(f"{a_file} is a file; choose another path\n")
    assert a_file.read_text() == "kept"


@pytest.mark.parametrize(
    ("module", "argv", "message"),
    [
        ("mobilemani_rl.envs.render_bench", ["--sizes", "0"], "argument --sizes: must be at least 1, got 0"),
        ("mobilemani_rl.envs.render_bench", ["--seconds", "0"], "argument --seconds: must be above 0, got 0"),
        ("mobilemani_rl.envs.render_bench", ["--object", "nope/0000"], "error: unknown object 'nope/0000'"),
        ("mobilemani_rl.envs.bench", ["--robots", "g1", "g2"], "argument --robots: invalid choice: 'g2'"),
        ("mobilemani_rl.envs.bench", ["--envs", "many"], "argument --envs: invalid count value: 'many'"),
        (
            "mobilemani_rl.rl.bench",
            ["--presets", "fast"],
            "argument --presets: invalid choice: 'fast'",
        ),
        ("mobilemani_rl.rl.sweep", ["--robot", "g2"], "argument --robot: invalid choice: 'g2'"),
        (
            "mobilemani_rl.envs.scene_sheet",
            ["--out", "x.png", "--size", "-5"],
            "argument --size: must be at least 1",
        ),
        (
            "mobilemani_rl.assets.__main__",
            ["preview", "--per-category", "0"],
            "--per-category: must be at least 1",
        ),
        # matplotlib and PIL refused these only after the half minute of rendering
        (
            "mobilemani_rl.assets.__main__",
            ["preview", "--out", "x.txt"],
            "argument --out: must name a .png file",
        ),
        (
            "mobilemani_rl.envs.scene_sheet",
            ["--out", "sheet"],
            "argument --out: must name a .png file, got sheet",
        ),
    ],
)
def test_command_line_tools_name_the_bad_option(module, argv, message, capsys, tmp_path, monkeypatch):
    """The argparse tools (benchmarks, sheets, sweeps) end bad input as the Hydra entry points do: exit 2 and
    one message naming the option and its valid values, before anything runs."""
    import importlib

    monkeypatch.chdir(tmp_path)
    main = importlib.import_module(module).main
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2 and message in capsys.readouterr().err
    assert not any(tmp_path.iterdir())

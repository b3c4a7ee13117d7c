"""Every command that writes checks its output location before any work starts: a file where a folder must go,
a read-only file system or a folder it may not write ends the command with one line naming the path, exit 2,
and nothing written anywhere."""

import errno
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace

import pytest
from checkout import ROOT, checkout_env
from data_helpers import tiny_cfg

import mobilemani_rl.utils.io
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.errors import InputError, UnwritableOutputError
from mobilemani_rl.utils.io import check_writable


def tree(root: Path) -> list[Path]:
    return sorted(p.relative_to(root) for p in root.rglob("*"))


def compose_root(name: str, overrides: list[str]):
    """The composed root config `name` (importing the config modules registers the roots' schemas)."""
    from hydra import compose, initialize_config_dir

    import mobilemani_rl.rl.config  # noqa: F401
    import mobilemani_vla.eval.config  # noqa: F401

    with initialize_config_dir(config_dir=str(ROOT / "conf"), version_base="1.3"):
        return compose(config_name=name, overrides=overrides)


# ------------------------------------------------------------------------------------------ the one check


def test_a_writable_location_passes_and_nothing_is_left_behind(tmp_path):
    assert check_writable(tmp_path / "a" / "b", "out") == tmp_path / "a" / "b"
    assert check_writable(str(tmp_path), "out") == tmp_path
    assert tree(tmp_path) == []  # neither the folder nor the probe file


def test_a_file_in_the_way_is_named(tmp_path):
    blocker = tmp_path / "notes.txt"
    blocker.write_text("kept")
    for folder in (blocker, blocker / "run" / "deeper"):
        with pytest.raises(UnwritableOutputError) as err:
            check_writable(folder, "run_dir")
        assert str(err.value) == f"cannot write {folder} (run_dir): {blocker} is a file; choose another path"
    assert isinstance(err.value, InputError) and blocker.read_text() == "kept"


def failing_probe(code: int, folder: Path) -> SimpleNamespace:
    """A stand-in for the tempfile module under which no file can be made in `folder`, as on a read-only file
    system mounted there (or a folder without write permission, for a user other than root)."""

    def mkstemp(prefix: str, dir: Path) -> tuple[int, str]:
        if Path(dir) == folder:
            raise OSError(
                code, {errno.EROFS: "Read-only file system", errno.EACCES: "Permission denied"}[code]
            )
        return tempfile.mkstemp(prefix=prefix, dir=dir)

    return SimpleNamespace(mkstemp=mkstemp)


@pytest.mark.parametrize(
    ("code", "reason"), [(errno.EROFS, "Read-only file system"), (errno.EACCES, "Permission denied")]
)
def test_a_location_that_refuses_the_probe_is_named_with_the_reason(tmp_path, monkeypatch, code, reason):
    monkeypatch.setattr(mobilemani_rl.utils.io, "tempfile", failing_probe(code, tmp_path))
    with pytest.raises(UnwritableOutputError) as err:
        check_writable(tmp_path / "out" / "run", "output_dir")
    assert str(err.value) == (
        f"cannot write {tmp_path / 'out' / 'run'} (output_dir): {tmp_path} is not writable ({reason}); "
        "choose another path"
    )


def test_a_real_folder_root_may_not_write_is_found_by_the_probe_not_by_os_access():
    """Tests run as root, whom permission bits do not stop; /sys refuses new files even to root (where it
    does not, this machine has no such folder to try)."""
    import os

    try:
        os.close((probe := tempfile.mkstemp(dir="/sys"))[0])
        os.unlink(probe[1])
        pytest.skip("/sys takes new files here")
    except OSError:
        pass
    with pytest.raises(
        UnwritableOutputError, match=r"^cannot write /sys/mobilemani/out \(out\): /sys is not"
    ):
        check_writable("/sys/mobilemani/out", "out")


# ------------------------------------------------------------------------------ every command that writes


def run_collect(out: Path, tmp: Path) -> None:
    from mobilemani_data.collect import collect

    collect(tiny_cfg(out))


def run_export(out: Path, tmp: Path) -> None:
    from mobilemani_data.export import export

    export(tiny_cfg(tmp / "data", f"dataset_dir={out / 'lerobot'}"))


def run_rl_train(out: Path, tmp: Path) -> None:
    from mobilemani_rl.rl.train import train

    train(compose_root("rl", ["rl/ppo=tiny", f"run_dir={out / 'run'}"]))


def run_teacher_sweep(out: Path, tmp: Path, option: str) -> None:
    from mobilemani_rl.rl.sweep import main

    paths = {"--runs": tmp / "runs", "--out": tmp / "tables", option: out / option[2:]}
    main(
        [
            "--robot",
            "g1",
            "--categories",
            "box",
            "--skills",
            "open",
            *(str(a) for p in paths.items() for a in p),
        ]
    )


def run_teacher_tables(out: Path, tmp: Path) -> None:
    from mobilemani_rl.rl.tables import main

    sys.argv = ["teacher_tables", str(tmp / "runs"), "--out", str(out / "rl")]
    main.__wrapped__()


def run_vla_train(out: Path, tmp: Path) -> None:
    from mobilemani_vla.config import compose_vla_cfg
    from mobilemani_vla.train import train

    train(compose_vla_cfg(["vla/model=tiny", f"data.root={tmp / 'none'}", f"train.output_dir={out / 'vla'}"]))


def run_evaluate(out: Path, tmp: Path) -> None:
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_vla.eval.config import EvalCfg
    from mobilemani_vla.eval.evaluate import evaluate

    overrides = ["eval/policy=scripted", "eval/protocol=small", f"output_dir={out / 'eval'}", "name=probe"]
    evaluate(to_dataclass(with_env_task(compose_root("eval", overrides)), EvalCfg).check())


def run_vla_tables(out: Path, tmp: Path) -> None:
    from mobilemani_vla.eval.tables import main

    sys.argv = ["tables", str(tmp / "eval"), "--out", str(out / "vla")]
    main.__wrapped__()


def run_ablation_study(out: Path, tmp: Path) -> None:
    from mobilemani_vla.ablation_study import main

    sys.argv = ["ablation_study", "--tables", str(out / "vla")]
    main.__wrapped__()


# command -> (how it runs, the output path its message names, the key that sets it)
COMMANDS: dict[str, tuple[Callable[[Path, Path], None], Callable[[Path], Path], str]] = {
    "collect": (run_collect, lambda out: out / "raw", "raw_dir"),
    "export": (run_export, lambda out: out / "lerobot", "dataset_dir"),
    "rl train": (run_rl_train, lambda out: out / "run", "run_dir"),
    "teacher sweep --runs": (
        lambda out, tmp: run_teacher_sweep(out, tmp, "--runs"),
        lambda out: out / "runs",
        "--runs",
    ),
    "teacher sweep --out": (
        lambda out, tmp: run_teacher_sweep(out, tmp, "--out"),
        lambda out: out / "out",
        "--out",
    ),
    "teacher tables": (run_teacher_tables, lambda out: out / "rl", "--out"),
    "vla train": (run_vla_train, lambda out: out / "vla", "train.output_dir"),
    "evaluate": (run_evaluate, lambda out: out / "eval" / "g1" / "probe", "output_dir"),
    "vla tables": (run_vla_tables, lambda out: out / "vla", "--out"),
    "ablation study": (run_ablation_study, lambda out: out / "vla", "--tables"),
}


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """tmp_path as the working directory, holding the one input the export needs to get as far as its output
    (a shard file); the commands' other inputs are never reached."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "argv", list(sys.argv))
    shard = tmp_path / "data" / "raw" / "g1" / "box" / "0000.h5"
    shard.parent.mkdir(parents=True)
    shard.touch()
    return tmp_path


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("fault", ["a file in the way", "a read-only file system"])
def test_every_writing_command_names_its_unwritable_output_in_one_line(
    workdir, command, fault, capsys, monkeypatch
):
    run, named, key = COMMANDS[command]
    if fault == "a file in the way":
        out = workdir / "notes.txt"
        out.write_text("kept")
        reason = f"{out} is a file"
    else:
        out = workdir / "read-only"
        out.mkdir()
        monkeypatch.setattr(mobilemani_rl.utils.io, "tempfile", failing_probe(errno.EROFS, out))
        reason = f"{out} is not writable (Read-only file system)"
    before = tree(workdir)
    with pytest.raises(SystemExit) as stop:
        entry_point(run)(out, workdir)
    err = capsys.readouterr().err
    assert stop.value.code == 2
    assert err == f"error: cannot write {named(out)} ({key}): {reason}; choose another path\n"
    assert tree(workdir) == before
    if fault == "a file in the way":
        assert out.read_text() == "kept"


@pytest.mark.parametrize(
    ("argv", "named", "key"),
    [
        (["-m", "mobilemani_rl.rl.train", "rl/ppo=tiny", "run_dir={out}/run"], "{out}/run", "run_dir"),
        (
            ["-m", "mobilemani_rl.rl.sweep", "--runs", "{out}/runs", "--out", "tables"],
            "{out}/runs",
            "--runs",
        ),
    ],
    ids=["rl train", "teacher sweep"],
)
def test_the_command_line_ends_with_one_line_and_writes_nothing(tmp_path, argv, named, key):
    """As a user runs them (a Hydra entry point, an argparse one): exit 2, the one line, nothing written."""
    out = tmp_path / "notes.txt"
    out.write_text("kept")
    done = subprocess.run(
        [sys.executable, *(a.format(out=out) for a in argv)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env={**checkout_env(), "OMP_NUM_THREADS": "1"},
    )
    assert done.returncode == 2
    message = f"error: cannot write {named.format(out=out)} ({key}): {out} is a file; choose another path\n"
    assert done.stderr.endswith(message) and done.stderr.count("\n") == 1, done.stderr
    assert tree(tmp_path) == [Path("notes.txt")] and out.read_text() == "kept"

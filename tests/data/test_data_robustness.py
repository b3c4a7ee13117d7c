"""Interrupted collection resumes without duplicates; corrupt shards are named and left out of the export."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from checkout import ROOT
from data_helpers import tiny_cfg

from mobilemani_data.collect import collect
from mobilemani_data.combos import shard_path
from mobilemani_data.export import export
from mobilemani_data.metadata import open_dataset_metadata, read_episodes, read_export_report
from mobilemani_data.parts import parts_dir
from mobilemani_data.shards import PARTIAL_SUFFIX, read_shard, shard_paths
from mobilemani_data.validate import validate
from mobilemani_rl.envs.tasks import select_combinations
from mobilemani_rl.utils.errors import ConfigMismatchError, InputError, MissingFileError
from mobilemani_rl.utils.writer_lock import WriterLock

# One object, both skills, both scenes: four shards.
SUBSET = ["subset.objects=[dishwasher/0000]", "subset.episodes=2"]


def start_collection(overrides: list[str]) -> subprocess.Popen:
    """`python -m mobilemani_data.collect` as a terminal starts it: its own process group, SIGINT handled
    (a background job of a shell would ignore it)."""
    return subprocess.Popen(
        [sys.executable, "-m", "mobilemani_data.collect", *overrides],
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def wait_for_a_shard(proc: subprocess.Popen, raw: Path) -> None:
    """Until the collection has written its first shard (or ended, or 120 s passed)."""
    deadline = time.time() + 120
    while not shard_paths(raw, "g1") and time.time() < deadline and proc.poll() is None:
        time.sleep(0.01)


def test_killed_collection_reruns_to_exact_counts(tmp_path):
    overrides = [f"data_dir={tmp_path}", "data/subset=tiny", *SUBSET, "collect.num_envs=8"]
    proc = start_collection(overrides)
    raw = tmp_path / "raw"
    wait_for_a_shard(proc, raw)
    proc.kill()
    proc.wait()
    done = shard_paths(raw, "g1")
    assert 1 <= len(done) < 4, "the kill should land between the first and the last shard"
    first = {p: p.stat().st_mtime_ns for p in done}
    # A write cut short leaves a truncated partial file; the rerun must neither read nor keep it.
    cfg = tiny_cfg(tmp_path, *SUBSET)
    missing = next(
        p for c in select_combinations(cfg.robot, cfg.subset) if not (p := raw / shard_path(c)).exists()
    )
    missing.parent.mkdir(parents=True, exist_ok=True)
    missing.with_name(missing.name + PARTIAL_SUFFIX).write_bytes(b"\x89HDF\r\n\x1a\n truncated")

    collect(cfg)
    paths = shard_paths(raw, "g1")
    assert len(paths) == 4
    assert all(len(read_shard(p).episodes) == 2 for p in paths)
    assert not list(raw.rglob(f"*{PARTIAL_SUFFIX}"))
    assert all(p.stat().st_mtime_ns == mtime for p, mtime in first.items())  # complete shards untouched


def running(pid: int) -> bool:
    """Whether the process exists and is not a zombie waiting to be reaped (Linux /proc)."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(") ", 1)[1][0] != "Z"
    except FileNotFoundError:
        return False


def child_pids(pid: int) -> list[int]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(child) for child in path.read_text().split()] if path.exists() else []


def command_line(pid: int) -> str:
    """The process's command line ('' once it is gone), to name a process left running."""
    try:
        return Path(f"/proc/{pid}/cmdline").read_text().replace("\0", " ")
    except FileNotFoundError:
        return ""


def still_running_after(pids: list[int], seconds: float) -> list[str]:
    """The command lines of those of `pids` still running once `seconds` have passed (or all have ended)."""
    deadline = time.time() + seconds
    while any(running(pid) for pid in pids) and time.time() < deadline:
        time.sleep(0.1)
    return [command_line(pid) for pid in pids if running(pid)]


@pytest.mark.slow
@pytest.mark.parametrize("stop", ["kill -9", "Ctrl-C"])
def test_workers_of_a_stopped_collection_stop_and_the_rerun_fills_in_the_rest(tmp_path, stop):
    """SIGKILL reaches only the parent, Ctrl-C the whole group: either way no worker may go on writing shards
    beside a rerun."""
    overrides = [f"data_dir={tmp_path}", "data/subset=tiny", *SUBSET, "collect.num_envs=8"]
    proc = start_collection([*overrides, "collect.workers=2"])
    raw = tmp_path / "raw"
    wait_for_a_shard(proc, raw)
    children = child_pids(proc.pid)
    if stop == "kill -9":
        proc.kill()
    else:
        os.killpg(proc.pid, signal.SIGINT)
    proc.wait(timeout=60)
    assert len(children) >= 2, "two workers (and multiprocessing's resource tracker) should have started"
    assert not still_running_after(children, seconds=10)

    collect(tiny_cfg(tmp_path, *SUBSET))
    paths = shard_paths(raw, "g1")
    assert len(paths) == 4
    assert all(len(read_shard(p).episodes) == 2 for p in paths)
    assert not list(raw.rglob(f"*{PARTIAL_SUFFIX}"))


def test_a_worker_still_starting_when_its_caller_is_killed_exits_too():
    """Killed while its workers still import (spawn), the caller leaves no worker behind: one that read its
    parent from os.getppid() after the kill waited on the dead caller's queue forever."""
    pool_run = "import operator; from mobilemani_rl.utils.process_pool import run_in_pool; "
    pool_run += "list(run_in_pool(operator.is_, [1, 2], workers=2))"
    caller = subprocess.Popen([sys.executable, "-c", pool_run], cwd=ROOT)
    children: list[int] = []
    deadline = time.time() + 60
    while not any("spawn_main" in command_line(pid) for pid in children):
        assert time.time() < deadline, "no worker started"
        time.sleep(0.01)
        children = child_pids(caller.pid)
    caller.kill()
    caller.wait(timeout=60)
    assert not still_running_after(children, seconds=10)


def test_two_workers_collect_the_episodes_of_one_process(tmp_path, capsys):
    """Combinations spread over two worker processes give one process's shards, array by array."""
    shards = {}
    for workers in (1, 2):
        collect(tiny_cfg(tmp_path / str(workers), *SUBSET, f"collect.workers={workers}"))
        paths = shard_paths(tmp_path / str(workers) / "raw", "g1")
        shards[workers] = {p.relative_to(tmp_path / str(workers)): read_shard(p) for p in paths}
    assert len(shards[2]) == 4 and shards[2].keys() == shards[1].keys()
    for name, shard in shards[2].items():
        alone = shards[1][name]
        assert shard.header["seed"] == alone.header["seed"]
        assert len(shard.episodes) == len(alone.episodes) == 2
        for ours, theirs in zip(shard.episodes, alone.episodes, strict=True):
            assert ours.arrays.keys() == theirs.arrays.keys()
            assert all(np.array_equal(ours.arrays[k], theirs.arrays[k]) for k in ours.arrays), name
    assert "| 4/4 combinations, " in capsys.readouterr().out


def test_a_rerun_asking_for_other_episodes_stops_before_collecting(tmp_path):
    """Complete shards are skipped on a rerun, so one made with another episode count, teacher, seed or action
    noise would pass for what the rerun asks: the rerun names the shard and the change and writes nothing."""
    one_skill = ["subset.objects=[dishwasher/0000]", "subset.skills=[open]"]
    collect(tiny_cfg(tmp_path, *one_skill, "subset.episodes=1"))
    written = {p: p.stat().st_mtime_ns for p in shard_paths(tmp_path / "raw", "g1")}
    for change, message in (
        ("subset.episodes=2", r"\(requested: 1 -> 2\)"),
        ("collect.action_noise=0.3", r"\(action_noise: 0.0 -> 0.3\)"),
        ("data/teacher=ppo", r"\(teacher: scripted -> ppo\)"),
    ):
        with pytest.raises(ConfigMismatchError, match=r"2 complete shard\(s\) .*" + message):
            collect(tiny_cfg(tmp_path, *one_skill, "subset.episodes=1", change))
    assert {p: p.stat().st_mtime_ns for p in shard_paths(tmp_path / "raw", "g1")} == written
    assert not list((tmp_path / "raw").rglob(f"*{PARTIAL_SUFFIX}"))


def test_missing_ppo_teachers_are_named_before_anything_is_written(tmp_path):
    cfg = tiny_cfg(tmp_path, "data/teacher=ppo", f"teacher.runs_dir={tmp_path / 'runs'}")
    with pytest.raises(MissingFileError, match=r"for 4 of 4 object-skill tasks \(cart/0000 pull, "):
        collect(cfg)
    assert not (tmp_path / "raw").exists()


def test_a_second_collection_or_export_of_the_same_output_stops(tmp_path):
    """One collection per shard of a data_dir (the jobs of a sharded multirun share it) and one export per
    dataset; the second stops at once, naming what the first is writing."""
    one_skill = ["subset.objects=[dishwasher/0000]", "subset.skills=[open]", "subset.episodes=1"]
    raw = tmp_path / "raw"
    with WriterLock(raw / "collect.lock", "a first collection"):
        with pytest.raises(InputError, match=f"another collection is writing {raw}; wait for it"):
            collect(tiny_cfg(tmp_path, *one_skill))
        assert not shard_paths(raw, "g1")
    with WriterLock(raw / "collect.shard-0-of-2.lock", "the job of shard 0"):
        with pytest.raises(InputError, match=r"writing .*raw \(shard.index=0 of 2\)"):
            collect(tiny_cfg(tmp_path, *one_skill, "shard.index=0", "shard.count=2"))
        collect(tiny_cfg(tmp_path, *one_skill, "shard.index=1", "shard.count=2"))  # the other shard runs
    assert len(shard_paths(raw, "g1")) == 1
    cfg = tiny_cfg(tmp_path, *one_skill)
    dataset = Path(cfg.dataset_dir)
    with WriterLock(dataset.with_name(dataset.name + ".lock"), "a first export"):
        with pytest.raises(InputError, match=f"another export is writing {dataset}; wait for it"):
            export(cfg)
    assert not dataset.exists() and not Path(cfg.dataset_dir + ".partial").exists()
    assert export(cfg).episodes == 1


def test_corrupt_shard_is_named_and_the_rest_exports(tmp_path, capsys):
    cfg = tiny_cfg(tmp_path, "subset.objects=[dishwasher/0000]", "subset.skills=[open]", "subset.episodes=1")
    collect(cfg)
    out = capsys.readouterr().out  # the total up front, then progress with an ETA
    assert (
        "2 combinations: 0 complete, 2 to collect" in out and "| 2/2 combinations, " in out and "ETA" in out
    )
    good, bad = shard_paths(Path(cfg.raw_dir), "g1")
    data = bad.read_bytes()
    bad.write_bytes(data[: len(data) // 2])

    problems = validate(cfg)
    assert len(problems) == 1 and str(bad) in problems[0]

    report = export(cfg)
    assert len(report.skipped) == 1 and str(bad) in report.skipped[0]
    lines = read_episodes(Path(cfg.dataset_dir))
    assert [line["shard"] for line in lines] == [str(good.relative_to(cfg.raw_dir))]
    assert read_export_report(Path(cfg.dataset_dir))["skipped"] == report.skipped
    assert not Path(cfg.dataset_dir + ".partial").exists()
    shutil.rmtree(cfg.dataset_dir)


def test_a_video_cut_short_is_named_by_validation_and_by_the_frame_cache(tmp_path):
    """Both ended in a decoder's traceback (LeRobot's FrameTimestampError, PyAV's InvalidDataError)."""
    from mobilemani_vla.data.frame_cache import cached_images

    cfg = tiny_cfg(tmp_path, "subset.objects=[dishwasher/0000]", "subset.skills=[open]", "subset.episodes=1")
    collect(cfg)
    export(cfg)
    root = Path(cfg.dataset_dir)
    meta = open_dataset_metadata(cfg.export.repo_id, root)
    video = root / meta.get_video_file_path(1, "observation.images.head_rgb")
    video.write_bytes(video.read_bytes()[: video.stat().st_size // 3])
    problems = validate(cfg)
    assert problems and all("does not decode" in p and str(video) in p for p in problems)
    with pytest.raises(InputError, match=f"frames do not decode from {video} .*the video is damaged"):
        cached_images(root, meta, ["head_rgb"], 32, progress=False)
    assert not (root / "vla_cache" / "head_rgb_32px").exists()


def test_a_rerun_reuses_an_up_to_date_export_and_a_changed_shard_needs_overwrite(tmp_path):
    cfg = tiny_cfg(tmp_path, "subset.objects=[dishwasher/0000]", "subset.skills=[open]", "subset.episodes=1")
    collect(cfg)
    first = export(cfg)
    assert not first.reused and first.episodes == 2
    again = export(cfg)
    assert again.reused and (again.episodes, again.frames) == (first.episodes, first.frames)
    shard = shard_paths(tmp_path / "raw", "g1")[0]
    os.utime(shard, ns=(shard.stat().st_atime_ns, shard.stat().st_mtime_ns + 1))  # as a re-collected shard
    with pytest.raises(FileExistsError, match="export.overwrite=true"):
        export(cfg)
    cfg.export.overwrite = True
    assert not export(cfg).reused and validate(cfg) == []


@pytest.mark.slow
def test_killed_export_leaves_nothing_complete_and_the_rerun_exports_everything(tmp_path):
    subset = ["subset.objects=[dishwasher/0000]", "subset.episodes=2"]
    cfg = tiny_cfg(tmp_path, *subset)
    collect(cfg)
    overrides = [
        f"data_dir={tmp_path}",
        "data/subset=tiny",
        *subset,
        "export.width=64",
        "export.height=64",
        "export.vcodec=h264",
        "export.combinations_per_part=1",
    ]
    proc = subprocess.Popen(
        [sys.executable, "-m", "mobilemani_data.export", *overrides],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    # A line per part (here one shard) once it is rendered: kill after the first of four.
    line = ""
    while "episodes" not in line and proc.poll() is None:
        line = proc.stdout.readline()
    proc.kill()
    proc.wait()
    assert "episodes" in line
    root = Path(cfg.dataset_dir)
    assert not root.exists() and (parts_dir(root) / "part-00000").is_dir()
    report = export(cfg)
    assert (report.episodes, report.skipped) == (8, []) and validate(cfg) == []
    assert not root.with_name(root.name + ".partial").exists() and not parts_dir(root).exists()

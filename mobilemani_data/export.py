"""Replay raw shards, render head and wrist cameras, and write a LeRobot v3 dataset:

    python -m mobilemani_data.export robot=g1 [export.width=224 export.height=224] [export.overwrite=true]
        [export.episodes_per_combination=1] [export.workers=2]

The dataset holds the subset's combinations (data/subset=..., as collected), not every shard under raw_dir;
combinations without a shard (not collected, or left out for a weak teacher) are counted and skipped.
`export.episodes_per_combination=k` keeps the first k episodes of each shard, those a collection of k would
have kept. The combinations are rendered in parts (`mobilemani_data.parts`), side by side on
`export.workers` worker processes, each part into a LeRobot dataset of its own under `<dataset>.parts/`,
which are merged into the dataset at the end. An interrupted export keeps its finished parts: the rerun
renders only the others, and the dataset is written next to its final place and renamed when finalized, so
it never looks complete before it is; `<dataset>.lock` beside it keeps a second export of the same dataset
out.
A shard that cannot be read is reported by name and left out; the others are exported.
Non-finite values are skipped, not exported and not fatal: an episode with a NaN or an infinity in any float
array (recorded in its shard, or in the vectors converted from it) is left out before it is rendered, with a
warning naming the shard, episode, key and first row; the summary counts such episodes and the export report
lists them (`skipped_episodes`). One bad episode among many thousands then costs neither the rest of a long
export nor a training label; like a skipped shard, it makes the command exit with status 1 once the rest is
written, so that it is not missed (`python -m mobilemani_data.validate` names it too).
Where the dataset goes is checked for writability before the lock is taken and anything is rendered.
A rerun on the same shards with the same settings (recorded in the export report) renders nothing;
`export.overwrite=true` replaces a dataset exported from other shards or settings.
Episode metadata (robot, object, category, skill, scene, split, ...) goes to `schema.EPISODES_FILE`.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # this command renders offscreen; mujoco reads it when imported

import json
import shutil
import sys
import time
import zlib
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import hydra
import numpy as np
from lerobot.configs.video import RGBEncoderConfig
from lerobot.datasets.lerobot_dataset import LeRobotDataset
from omegaconf import DictConfig

from mobilemani_data import schema
from mobilemani_data.config import DataCfg, ExportCfg
from mobilemani_data.convert import FIRST_FRAME, camera_images, episode_vectors
from mobilemani_data.frame import robot_cameras
from mobilemani_data.parts import (
    PARTIAL,
    Part,
    finished_manifest,
    merge_parts,
    parts_dir,
    plan_parts,
    seal_part,
)
from mobilemani_data.replay import Replayer
from mobilemani_data.shards import Shard, ShardError, read_shard
from mobilemani_data.teachers import kind_of
from mobilemani_rl.assets.robots import RobotDescription, get_robot
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.envs.tasks import select_combinations
from mobilemani_rl.render import CameraRenderCfg, CameraRenderer
from mobilemani_rl.render.appearance import RoomRepainter
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.errors import MissingFileError, OutputExistsError
from mobilemani_rl.utils.io import check_writable, non_finite, read_json
from mobilemani_rl.utils.process_pool import run_in_pool
from mobilemani_rl.utils.progress import Progress
from mobilemani_rl.utils.video_logs import quiet_video_libraries
from mobilemani_rl.utils.writer_lock import WriterLock, busy


@dataclass
class ExportReport:
    root: Path
    episodes: int = 0
    frames: int = 0
    skipped: list[str] = field(default_factory=list)  # one message per shard left out
    skipped_episodes: list[str] = field(default_factory=list)  # one message per non-finite episode left out
    empty: list[str] = field(default_factory=list)  # one message per shard without an episode (no success)
    render_s: float = 0.0
    total_s: float = 0.0
    reused: bool = False  # the dataset was already up to date: nothing was rendered
    rendered_frames: int = 0  # frames rendered by this run (parts finished by an interrupted run are kept)
    missing: int = 0  # combinations of the subset without a shard


def image_keys(cfg: ExportCfg) -> list[str]:
    return [schema.image_key(c, m) for c in cfg.cameras for m in cfg.modalities]


def create_dataset(root: Path, robot: RobotDescription, cfg: ExportCfg) -> LeRobotDataset:
    features = schema.features(
        robot.action_dim,
        len(robot.hand_joints),
        cfg.height,
        cfg.width,
        tuple(cfg.cameras),
        tuple(cfg.modalities),
    )
    encoder = RGBEncoderConfig(vcodec=cfg.vcodec, crf=cfg.crf, g=cfg.gop, preset=cfg.preset)
    return LeRobotDataset.create(
        cfg.repo_id,
        fps=schema.FPS,
        features=features,
        root=root,
        robot_type=robot.name,
        use_videos=True,
        video_backend="pyav",
        rgb_encoder=encoder,
        streaming_encoding=cfg.streaming_encoding,
    )


def label_window(cfg: ExportCfg, teacher: str) -> int:
    """The smoothing window of a shard's labels: `ppo_label_window` for a PPO teacher's, none for the
    scripted teacher's (smooth already)."""
    return cfg.ppo_label_window if kind_of(teacher) == "ppo" else 1


def add_shard(
    ds: LeRobotDataset,
    shard: Shard,
    robot: RobotDescription,
    cfg: ExportCfg,
    raw_dir: Path,
    report: ExportReport,
) -> list[dict]:
    """Render and save the shard's episodes (at most `cfg.episodes_per_combination`, the first finite ones);
    returns their metadata lines."""
    replayer = Replayer(shard)
    cameras = {name: mj_camera for name, mj_camera in robot_cameras(robot).items() if name in cfg.cameras}
    keys = image_keys(cfg)
    renderer = CameraRenderer(
        replayer.model,
        CameraRenderCfg(
            width=cfg.width,
            height=cfg.height,
            cameras=tuple(cameras.values()),
            segmentation="seg" in cfg.modalities,
        ),
    )
    repainter = RoomRepainter(replayer.model) if cfg.room_repaint > 0 else None
    window = label_window(cfg, shard.header["teacher"])
    lines = []
    try:
        for k, episode in enumerate(shard.episodes):
            if len(lines) == cfg.episodes_per_combination:
                break
            if repainter is not None:  # seeded by shard and episode: a rerun renders the same images
                seed = zlib.crc32(f"{shard.path.relative_to(raw_dir)}/{k}".encode())
                repainter.repaint(np.random.default_rng(seed), cfg.room_repaint)
            vectors = {}
            bad = non_finite(episode.arrays)
            if not bad:  # the converted vectors are the labels: they must be finite too
                vectors = episode_vectors(episode, len(robot.hand_joints), cfg.action_convention, window)
                bad = non_finite(vectors)
            if bad:
                key, row, value = bad[0]
                message = f"{shard.path}: episode {k} {key} row {row} is not finite ({value})"
                report.skipped_episodes.append(message)
                print(f"skipped episode {message}", file=sys.stderr, flush=True)
                continue
            for i, state in enumerate(episode.arrays["state"][FIRST_FRAME:]):
                start = time.perf_counter()
                frame = camera_images(renderer, replayer, state, cameras, keys)
                report.render_s += time.perf_counter() - start
                frame.update({name: values[i] for name, values in vectors.items()})
                frame["task"] = shard.header["instruction"]
                ds.add_frame(frame)
            ds.save_episode()
            length = episode.length - FIRST_FRAME
            lines.append(
                {
                    "episode_index": report.episodes,
                    **{key: shard.header[key] for key in schema.EPISODE_METADATA},
                    "scene_split": shard.header["scene_split"],
                    "instruction": shard.header["instruction"],
                    "teacher": shard.header["teacher"],
                    "length": length,
                    "shard": str(shard.path.relative_to(raw_dir)),
                    "shard_episode": k,
                    "env_slot": episode.attrs["env_slot"],
                    "round": episode.attrs["round"],
                }
            )
            report.episodes += 1
            report.frames += length
    finally:
        renderer.close()
    return lines


def export_source(cfg: ExportCfg, raw_dir: Path, paths: list[Path]) -> dict:
    """What a dataset is exported from: the settings that shape its files, every shard's size and mtime."""
    settings = {
        k: getattr(cfg, k)
        for k in (
            "repo_id",
            "width",
            "height",
            "vcodec",
            "crf",
            "gop",
            "preset",
            "action_convention",
            "room_repaint",
            "ppo_label_window",
            "episodes_per_combination",
        )
    }
    shards = {str(p.relative_to(raw_dir)): [(st := p.stat()).st_size, st.st_mtime_ns] for p in paths}
    return {**settings, "cameras": list(cfg.cameras), "modalities": list(cfg.modalities), "shards": shards}


def up_to_date_report(root: Path, source: dict) -> dict | None:
    """The dataset's export report when it was exported from `source`, else None."""
    path = root / schema.EXPORT_REPORT_FILE
    report = read_json(path) if path.is_file() else {}
    return report if report.get("source") == source else None


def export(cfg: DataCfg) -> ExportReport:
    robot = get_robot(cfg.robot)
    raw_dir, root = Path(cfg.raw_dir), Path(cfg.dataset_dir)
    check_writable(root, "dataset_dir")  # the dataset, or the folder its .partial, .parts and .lock go into
    check_writable(root.parent, "dataset_dir")
    combos = select_combinations(robot.name, cfg.subset)
    parts, missing = plan_parts(combos, raw_dir, cfg.export.combinations_per_part)
    if not parts:
        raise MissingFileError(
            f"none of the subset's {len(combos)} combinations has a shard under {raw_dir / robot.name} "
            "(run python -m mobilemani_data.collect with the same data/subset)"
        )
    with WriterLock(root.with_name(root.name + ".lock"), busy("export", root, "dataset_dir")):
        report = export_parts(cfg, raw_dir, root, parts)
    report.missing = missing
    return report


def export_parts(cfg: DataCfg, raw_dir: Path, root: Path, parts: list[Part]) -> ExportReport:
    """Render the parts into the dataset at `root` through `<root>.partial`, unless it is up to date."""
    paths = [path for part in parts for path in part.shards]
    source = export_source(cfg.export, raw_dir, paths)
    # A rerun (make data, make demo) does not render the same dataset again.
    if (existing := up_to_date_report(root, source)) is not None:
        print(f"{root} is up to date with {len(paths)} shards and these export settings; skipped", flush=True)
        shutil.rmtree(parts_dir(root), ignore_errors=True)  # left by a run stopped just after its rename
        return ExportReport(
            root,
            existing["episodes"],
            existing["frames"],
            existing["skipped"],
            existing.get("skipped_episodes", []),
            existing.get("empty", []),
            reused=True,
        )
    if root.exists() and not cfg.export.overwrite:
        raise OutputExistsError(
            f"{root} exists and was exported from other shards or settings; "
            "pass export.overwrite=true to replace it"
        )
    start = time.perf_counter()
    folder = parts_dir(root)
    manifests = {}
    for part in parts:
        found = finished_manifest(folder / part.name, export_source(cfg.export, raw_dir, list(part.shards)))
        if found is not None:
            manifests[part.index] = found
    todo = [part for part in parts if part.index not in manifests]
    kept = f", {len(manifests)} finished before" if manifests else ""
    print(f"{len(paths)} shards in {len(parts)} parts{kept}, {len(todo)} to render", flush=True)
    report = ExportReport(root)
    progress = Progress(len(todo), "parts")
    # Each worker quiets its own encoders' logs (make_state: built once per worker, the state itself unused).
    for part, (manifest, seconds) in run_in_pool(
        partial(timed_part, cfg, folder), todo, cfg.export.workers, make_state=quiet_video_libraries
    ):
        manifests[part.index] = manifest
        report.render_s += manifest["render_s"]
        report.rendered_frames += manifest["frames"]
        print(
            f"{part.name}: {len(part.shards)} shards, {manifest['episodes']} episodes, {manifest['frames']} "
            f"frames ({seconds:.1f} s) | {progress.advance()}",
            flush=True,
        )
    merged = [manifests[part.index] for part in parts]
    for manifest in merged:
        report.skipped += manifest["skipped"]
        report.skipped_episodes += manifest["skipped_episodes"]
        report.empty += manifest.get("empty", [])  # parts sealed before shards could be empty hold none
    lines = [line for manifest in merged for line in manifest["lines"]]
    if not lines:
        raise ShardError(
            f"no readable shard with an episode among the subset's under {raw_dir / cfg.robot}: "
            f"{report.skipped + report.skipped_episodes + report.empty}"
        )
    tmp = root.with_name(root.name + PARTIAL)
    shutil.rmtree(tmp, ignore_errors=True)
    merge_parts(
        [folder / part.name for part, manifest in zip(parts, merged, strict=True) if manifest["lines"]],
        cfg.export.repo_id,
        tmp,
    )
    for index, line in enumerate(lines):  # numbered as the merged dataset numbers its episodes
        line["episode_index"] = index
    report.episodes, report.frames = len(lines), sum(line["length"] for line in lines)
    (tmp / schema.EPISODES_FILE).write_text("".join(json.dumps(line) + "\n" for line in lines))
    report.total_s = time.perf_counter() - start
    (tmp / schema.EXPORT_REPORT_FILE).write_text(
        json.dumps(
            {
                "episodes": report.episodes,
                "frames": report.frames,
                "skipped": report.skipped,
                "skipped_episodes": report.skipped_episodes,
                "empty": report.empty,
                "width": cfg.export.width,
                "height": cfg.export.height,
                "vcodec": cfg.export.vcodec,
                "cameras": list(cfg.export.cameras),
                "modalities": list(cfg.export.modalities),
                "action_convention": cfg.export.action_convention,
                "room_repaint": cfg.export.room_repaint,
                "episodes_per_combination": cfg.export.episodes_per_combination,
                "source": source,
            },
            indent=2,
        )
    )
    if root.exists():
        shutil.rmtree(root)
    tmp.rename(root)
    shutil.rmtree(folder)  # the parts' files are copied into the dataset
    return report


def render_part(cfg: DataCfg, folder: Path, part: Part) -> dict:
    """Render one part into `<folder>/<part>` (here or in a worker); returns its manifest: what it was
    rendered from, its episodes' metadata lines (numbered within the part), and what it left out."""
    robot, raw_dir = get_robot(cfg.robot), Path(cfg.raw_dir)
    target = folder / part.name
    tmp = target.with_name(target.name + PARTIAL)
    shutil.rmtree(tmp, ignore_errors=True)
    shutil.rmtree(target, ignore_errors=True)  # a part rendered from other shards or settings
    folder.mkdir(parents=True, exist_ok=True)
    report = ExportReport(target)
    ds = create_dataset(tmp, robot, cfg.export)
    lines: list[dict] = []
    for path in part.shards:
        try:
            shard = read_shard(path)
        except ShardError as err:
            report.skipped.append(str(err))
            print(f"skipped shard {err}", file=sys.stderr, flush=True)
            continue
        if not shard.episodes:  # the teacher failed every attempt: a fact of the data, not damage
            report.empty.append(f"{path}: no episode (collection found no success within its attempts)")
            continue
        lines += add_shard(ds, shard, robot, cfg.export, raw_dir, report)
    ds.finalize()
    manifest = {
        "source": export_source(cfg.export, raw_dir, list(part.shards)),
        "episodes": report.episodes,
        "frames": report.frames,
        "render_s": report.render_s,
        "skipped": report.skipped,
        "skipped_episodes": report.skipped_episodes,
        "empty": report.empty,
        "lines": lines,
    }
    seal_part(tmp, target, manifest)
    return manifest


def timed_part(cfg: DataCfg, folder: Path, _state: None, part: Part) -> tuple[dict, float]:
    """A part's manifest and its seconds, here or in a worker (`process_pool.run_in_pool`)."""
    start = time.perf_counter()
    manifest = render_part(cfg, folder, part)
    return manifest, time.perf_counter() - start


@hydra.main(config_path="../conf", config_name="data", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    quiet_video_libraries()
    report = export(to_dataclass(with_env_task(cfg), DataCfg).check())
    timing = (
        ""
        if report.reused
        else (
            f" in {report.total_s:.1f} s ({report.rendered_frames} rendered by this run, "
            f"{report.rendered_frames / max(report.total_s, 1e-9):.1f} frames/s)"
        )
    )
    print(
        f"{report.root}: {report.episodes} episodes, {report.frames} frames{timing}; "
        f"{report.missing} combinations without a shard, {len(report.skipped)} shards skipped, "
        f"{len(report.skipped_episodes)} non-finite episodes skipped, {len(report.empty)} combinations "
        "without an episode"
    )
    if report.skipped or report.skipped_episodes:
        sys.exit(1)


if __name__ == "__main__":
    main()

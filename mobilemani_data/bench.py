"""`python -m mobilemani_data.bench robot=g1 [bench.sizes=[224,520]] [bench.episodes=2]`: export throughput.

Collects `bench.episodes` scripted episodes of one combination into a temporary directory, then exports them
at each size with the configured codec: rendered + encoded frames per second (whole export wall time,
including replay, rendering of 2 cameras x RGB/depth/segmentation, encoding of 6 videos and parquet writing),
the share spent rendering, and the size on disk per episode (LeRobot dataset, and the raw HDF5 shard). Prints
JSON and a table; writes the JSON to bench.out.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # this command renders offscreen; mujoco reads it when imported

import json
import tempfile
from dataclasses import replace
from pathlib import Path

import hydra
from omegaconf import DictConfig

from mobilemani_data.collect import collect
from mobilemani_data.config import DataCfg
from mobilemani_data.export import export
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.envs.tasks import SubsetCfg
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.video_logs import quiet_video_libraries

BENCH_SUBSET = dict(objects=["dishwasher/0000"], skills=["open"], scenes_per_object=1)


def _bytes(path: Path) -> int:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())


def run_bench(cfg: DataCfg, workdir: Path) -> dict:
    cfg = replace(
        cfg, raw_dir=str(workdir / "raw"), subset=SubsetCfg(**BENCH_SUBSET, episodes=cfg.bench.episodes)
    )
    collect(cfg)
    raw_bytes = _bytes(workdir / "raw")
    results = []
    for size in cfg.bench.sizes:
        export_cfg = replace(cfg.export, width=size, height=size, overwrite=True)
        root = workdir / f"lerobot_{size}"
        report = export(replace(cfg, dataset_dir=str(root), export=export_cfg))
        results.append(
            {
                "size": size,
                "frames": report.frames,
                "frames_per_s": round(report.frames / report.total_s, 1),
                "render_share": round(report.render_s / report.total_s, 3),
                "episode_mb": round(_bytes(root) / report.episodes / 2**20, 3),
                "mean_episode_frames": round(report.frames / report.episodes, 1),
            }
        )
    return {
        "robot": cfg.robot,
        "subset": BENCH_SUBSET,
        "episodes": cfg.bench.episodes,
        "vcodec": cfg.export.vcodec,
        "crf": cfg.export.crf,
        "gop": cfg.export.gop,
        "raw_shard_mb_per_episode": round(raw_bytes / cfg.bench.episodes / 2**20, 3),
        "results": results,
    }


@hydra.main(config_path="../conf", config_name="data", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    quiet_video_libraries()
    data_cfg = to_dataclass(with_env_task(cfg), DataCfg).check()
    with tempfile.TemporaryDirectory(prefix="mobilemani_bench_") as tmp:
        report = run_bench(data_cfg, Path(tmp))
    out = Path(data_cfg.bench.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=2))
    print(json.dumps(report, indent=2))
    print(
        f"{'size':>5} {'frames/s (render+encode)':>25} {'render share':>13} {'MB/episode':>11} "
        f"{'frames/ep':>10}"
    )
    for r in report["results"]:
        print(
            f"{r['size']:>5} {r['frames_per_s']:>25} {r['render_share']:>13} {r['episode_mb']:>11} "
            f"{r['mean_episode_frames']:>10}"
        )
    print(f"raw HDF5 shard: {report['raw_shard_mb_per_episode']} MB/episode")


if __name__ == "__main__":
    main()

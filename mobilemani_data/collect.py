"""Collect successful teacher episodes into raw HDF5 shards, one per (robot, object, skill, scene):

    python -m mobilemani_data.collect robot=g1 data/subset=small [data/teacher=ppo] [subset.episodes=10]

Complete shards are skipped, so a rerun (or a resumed multirun job) only fills in what is missing; a killed
run leaves at most a `.partial` file, which the rerun overwrites. A rerun whose settings would have made other
episodes (teacher kind, episode count, seed, action noise) stops before collecting, as does one missing a PPO
teacher; combinations whose teacher trained below `teacher.min_train_success` are left out, with one line per
such teacher. The count of combinations to collect is printed up front, and every combination's line ends with
progress and an ETA. `collect.workers=N` collects N combinations side by side in worker processes, each on
an equal share of the CPU's threads; a combination's episodes depend only on its seed, not on the worker.
A second collection of the same shard into the same data_dir stops while the first runs (`collection_lock`).
A raw_dir that cannot be written (a file in the way, a read-only file system) stops before anything runs.
"""

from __future__ import annotations

import time
from functools import partial
from pathlib import Path

import hydra
from omegaconf import DictConfig, OmegaConf

from mobilemani_data import schema
from mobilemani_data.combos import shard_of, shard_path
from mobilemani_data.config import DataCfg, ShardCfg
from mobilemani_data.recorder import collect_successes
from mobilemani_data.shards import complete_header, write_shard
from mobilemani_data.teachers import build_teacher, current_teacher, teachable_combinations
from mobilemani_rl.envs.config import with_env_task
from mobilemani_rl.envs.tasks import Combination, select_combinations
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import changed_values, to_dataclass
from mobilemani_rl.utils.errors import ConfigMismatchError
from mobilemani_rl.utils.io import check_writable
from mobilemani_rl.utils.process_pool import run_in_pool, threads_per_worker
from mobilemani_rl.utils.progress import Progress
from mobilemani_rl.utils.writer_lock import WriterLock, busy


def episode_settings(cfg: DataCfg, combo: Combination, teacher: str) -> dict:
    """The settings besides the env that decide a combination's episodes, as its shard's header records
    them."""
    return {
        "teacher": teacher,
        "requested": cfg.subset.episodes,
        "seed": combo.seed(cfg.collect.seed),
        "action_noise": cfg.collect.action_noise,
    }


def check_complete_shards(cfg: DataCfg, done: list[tuple[Combination, Path, dict]]) -> None:
    """A complete shard made with other settings would be skipped as if it held what this run asks for."""
    mismatched = []
    for combo, path, header in done:
        saved = {key: header[key] for key in ("requested", "seed", "teacher")}
        saved["action_noise"] = header.get("action_noise", 0.0)  # shards from before DART have none
        wanted = episode_settings(cfg, combo, current_teacher(cfg.teacher, combo, header["teacher"]))
        if changes := changed_values(saved, wanted, tuple(wanted)):
            mismatched.append(f"{path} ({'; '.join(changes)})")
    if mismatched:
        raise ConfigMismatchError(
            f"{len(mismatched)} complete shard(s) in {cfg.raw_dir} were collected with other settings, e.g. "
            f"{mismatched[0]}; choose another data_dir=... or delete them to collect anew"
        )


def collect_combination(cfg: DataCfg, combo: Combination, path: Path) -> str:
    seed = combo.seed(cfg.collect.seed)
    teacher = build_teacher(cfg.teacher, combo, cfg.env, cfg.collect.num_envs, seed)
    rollouts = collect_successes(
        teacher.env,
        teacher.policy,
        cfg.subset.episodes,
        cfg.collect.max_steps,
        seed,
        cfg.collect.action_noise,
    )
    header = {
        **combo.metadata(),
        "instruction": combo.instruction,
        "teacher": teacher.name,
        "seed": seed,
        "action_noise": cfg.collect.action_noise,
        "fps": schema.FPS,
        "requested": cfg.subset.episodes,
        "attempts": rollouts.attempts,
        "steps": rollouts.steps,
        "capped": rollouts.capped,
        "env_cfg": OmegaConf.to_yaml(OmegaConf.structured(teacher.env.cfg)),
    }
    write_shard(path, header, rollouts.episodes, cfg.collect.compression)
    lengths = [ep.length for ep in rollouts.episodes]
    capped = " (step cap reached)" if rollouts.capped else ""
    return (
        f"{len(lengths)}/{cfg.subset.episodes} episodes from {rollouts.attempts} attempts{capped}, "
        f"mean length {sum(lengths) / max(1, len(lengths)):.0f}"
    )


def timed_collection(cfg: DataCfg, _state: None, item: tuple[int, Combination, Path]) -> tuple[str, float]:
    """A combination's summary line and its seconds, here or in a worker (`process_pool.run_in_pool`)."""
    _, combo, path = item
    start = time.perf_counter()
    summary = collect_combination(cfg, combo, path)
    return summary, time.perf_counter() - start


def collect(cfg: DataCfg) -> list[Path]:
    check_writable(cfg.raw_dir, "raw_dir")
    combos = shard_of(select_combinations(cfg.robot, cfg.subset), cfg.shard)
    paths = [Path(cfg.raw_dir) / shard_path(combo) for combo in combos]
    headers = [complete_header(path) for path in paths]
    check_complete_shards(cfg, [(c, p, h) for c, p, h in zip(combos, paths, headers, strict=True) if h])
    missing = [(k, c, p) for k, (c, p, h) in enumerate(zip(combos, paths, headers, strict=True)) if h is None]
    teachable, notes = teachable_combinations(cfg.teacher, [combo for _, combo, _ in missing])
    kept = set(teachable)
    todo = [item for item in missing if item[1] in kept]
    complete = len(combos) - len(missing)
    left_out = f"{len(missing) - len(todo)} left out, " if len(todo) < len(missing) else ""
    print(f"{len(combos)} combinations: {complete} complete, {left_out}{len(todo)} to collect", flush=True)
    for note in notes:
        print(note, flush=True)
    workers = min(cfg.collect.workers, len(todo))
    if workers > 1 and cfg.env.physics.nthread == 0:  # every worker on all cores would oversubscribe them
        cfg.env.physics.nthread = threads_per_worker(workers)
    shard = f" (shard.index={cfg.shard.index} of {cfg.shard.count})" if cfg.shard.count > 1 else ""
    with WriterLock(
        Path(cfg.raw_dir) / collection_lock(cfg.shard),
        busy("collection", f"{cfg.raw_dir}{shard}", "data_dir"),
    ):
        finished = run_in_pool(partial(timed_collection, cfg), todo, workers)
        progress = Progress(len(todo), "combinations")
        for (k, combo, _), (summary, seconds) in finished:
            print(
                f"[{k + 1}/{len(combos)}] {combo.name}: {summary} ({seconds:.1f} s) | {progress.advance()}",
                flush=True,
            )
    return paths


def collection_lock(shard: ShardCfg) -> str:
    """One lock per shard of the combinations: the jobs of a sharded multirun share a data_dir, and only two
    jobs on the same shard would collect the same combinations."""
    return "collect.lock" if shard.count == 1 else f"collect.shard-{shard.index}-of-{shard.count}.lock"


@hydra.main(config_path="../conf", config_name="data", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    collect(to_dataclass(with_env_task(cfg), DataCfg).check())


if __name__ == "__main__":
    main()

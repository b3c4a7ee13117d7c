"""A teacher for every category-skill row of a robot (the paper's teacher table), resumable:

    python -m mobilemani_rl.rl.sweep --robot g1 [--runs outputs/teachers]
        [--out outputs/teachers/tables/g1] [--categories box laptop] [--skills open]
        [--skill-iterations pick:3000] [--test-episodes 256]
        [hydra overrides, e.g. rl.ppo.max_iterations=300]

Each row trains one category-level policy on up to `objects_per_policy` of the category's train objects
(`python -m mobilemani_rl.rl.train robot=<robot> task.object=<category> task.skill=<skill>`) and evaluates it
on all of the category's train and test objects (`eval_episodes` seeded episodes each). Rows run one after
another; a row whose evaluation exists is skipped, as is one that `<out>/teachers_<robot>.json` records with
the same command while its run directory is gone (finished on another machine), and an interrupted row resumes
from its newest checkpoint (training's own resume), so rerunning the same command continues where it stopped;
a finished row asked for more iterations goes on to them, and one asked for other settings stops the sweep
before anything trains, naming them. `--skill-iterations SKILL:N` gives that skill's rows their own iteration
count (holistic pick is still learning when 300 end); `--test-episodes N` gives a category with few test
objects more episodes per object, so that every row's test success counts at least N episodes. After every row
the sweep rewrites `<out>/teachers_<robot>.json` and `.md` with every row finished so far, also by earlier
runs over other rows (per row: test and train success, the warm start's scripted success, samples, wall
minutes, the command that recreates it; rows below the paper's skill mean with the stage they fall short in),
and the paper's teacher tables computed from those rows' test objects (`rl_by_skill`, `rl_by_category`);
where `--out` is named after the robot (`make teachers`' `TEACHERS_OUT/<robot>`), the same tables with both
robots' columns, from every `TEACHERS_OUT/<robot>/teachers_<robot>.json`, go to `TEACHERS_OUT`.
Checkpoints stay under `--runs`. Both `--runs` and `--out` are checked for writability before the first row
trains.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from hydra import compose, initialize_config_dir
from omegaconf import DictConfig

from mobilemani_rl.assets.objects import ALL_SKILLS, CATEGORIES, catalog_ids
from mobilemani_rl.rl.config import RLCfg
from mobilemani_rl.rl.eval import evaluate
from mobilemani_rl.rl.run_dir import RESULT, WARM_START, is_complete, latest_checkpoint
from mobilemani_rl.rl.tables import (
    PAPER_BY_SKILL,
    ROBOTS,
    rows,
    write_tables,
)
from mobilemani_rl.rl.train import check_run, train
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import CONF_DIR, to_dataclass
from mobilemani_rl.utils.errors import InputError, check_choice
from mobilemani_rl.utils.io import check_writable, read_json, write_json_atomic
from mobilemani_rl.utils.table_format import pct

EVAL_EPISODES = 64  # per evaluated object, unless --test-episodes asks for more
EVAL_SEED = 1000  # the seed `python -m mobilemani_rl.rl.train eval_episodes=N` evaluates with
WALL = "sweep_seconds.json"  # wall seconds of a row, summed over its finished or Ctrl-C'd attempts
WEAKEST = 2  # test objects named in a low row's diagnosis


ITERATIONS = "rl.ppo.max_iterations="


def row_overrides(
    robot: str,
    category: str,
    skill: str,
    runs: Path,
    overrides: list[str],
    iterations: int | None = None,
    test_episodes: int = 0,
) -> list[str]:
    """The row's training command (as Hydra overrides); the evaluation's episodes default to 64 per object,
    raised where the category's test objects would get fewer than `test_episodes` in all, and `iterations`
    (the skill's own count) replaces any iteration override."""
    test_objects = len(catalog_ids(category, "test")) or 1
    per_object = max(EVAL_EPISODES, -(-test_episodes // test_objects))
    default = (
        [] if any(o.startswith("eval_episodes=") for o in overrides) else [f"eval_episodes={per_object}"]
    )
    if iterations is not None:
        overrides = [*(o for o in overrides if not o.startswith(ITERATIONS)), f"{ITERATIONS}{iterations}"]
    return [
        *default,
        f"robot={robot}",
        f"task.object={category}",
        f"task.skill={skill}",
        f"run_dir={runs / robot / category / skill}",
        *overrides,
    ]


def skill_iterations(text: str) -> tuple[str, int]:
    """'pick:3000' -> ('pick', 3000), for --skill-iterations."""
    skill, _, count = text.partition(":")
    check_choice(skill, ALL_SKILLS, "--skill-iterations skill")
    if not count.isdigit() or int(count) < 1:
        raise InputError(f"--skill-iterations {text}: expected SKILL:N with N >= 1, e.g. pick:3000")
    return skill, int(count)


def evaluation_file(run_dir: Path) -> Path | None:
    checkpoint = latest_checkpoint(run_dir) if is_complete(run_dir) else None
    if checkpoint is None:
        return None
    path = run_dir / f"eval_{checkpoint.stem}_{EVAL_SEED}.json"
    return path if path.is_file() else None


def checked_row_config(overrides: list[str]) -> DictConfig:
    """The row's composed config, every value checked (before any row trains)."""
    with initialize_config_dir(config_dir=str(CONF_DIR), version_base="1.3"):
        cfg = compose(config_name="rl", overrides=overrides)
    if to_dataclass(cfg, RLCfg).check().eval_episodes < 1:
        raise InputError("eval_episodes must be >= 1: every row is evaluated on its test objects")
    return cfg


def spent_seconds(run_dir: Path) -> float | None:
    path = run_dir / WALL
    return read_json(path)["seconds"] if path.is_file() else None


def run_row(cfg: DictConfig) -> None:
    """Train (or resume) the row's policy, then evaluate its final checkpoint; adds the wall time spent."""
    run_dir = Path(cfg.run_dir)
    start = time.time()
    try:
        train(cfg)
        evaluate(latest_checkpoint(run_dir), cfg.eval_episodes, seed=EVAL_SEED)
    finally:  # an interrupted (Ctrl-C) attempt's time counts too; a killed one's is lost
        if run_dir.is_dir():
            spent = (spent_seconds(run_dir) or 0) + time.time() - start
            write_json_atomic(run_dir / WALL, {"seconds": round(spent, 1)})


def warm_start_success(run_dir: Path) -> float | None:
    """The scripted demonstrations' success on the trained objects (None: trained from scratch)."""
    path = run_dir / WARM_START
    return read_json(path)["scripted_success"] if path.is_file() else None


def row_record(robot: str, category: str, skill: str, run_dir: Path, command: str) -> dict:
    """What the tables need from a finished row: success on test and on trained objects, cost, command."""
    evaluation = read_json(evaluation_file(run_dir))
    result = read_json(run_dir / RESULT)
    objects = evaluation["objects"]
    test = {i: o["success_rate"] for i, o in objects.items() if o["split"] == "test"}
    return {
        "robot": robot,
        "category": category,
        "skill": skill,
        "test_success": float(np.mean(list(test.values()))) if test else None,
        "train_success": evaluation["success_rate"],  # the trained objects
        "scripted_success": warm_start_success(run_dir),
        "test_object_success": test,
        "test_objects": len(test),
        "trained_objects": sum(o["trained"] for o in objects.values()),
        "episodes_per_object": evaluation["episodes_per_object"],
        "samples": result["samples"],
        "wall_minutes": None if (spent := spent_seconds(run_dir)) is None else round(spent / 60, 1),
        "command": command,
    }


def paper_skill_mean(robot: str, skill: str) -> float:
    return PAPER_BY_SKILL[skill][ROBOTS.index(robot)] / 100.0


def diagnosis(record: dict) -> str:
    """Where a row below the paper's skill mean falls short: on unseen objects only, or in training too."""
    train, scripted = record["train_success"], record["scripted_success"]
    weakest = sorted(record["test_object_success"].items(), key=lambda item: item[1])[:WEAKEST]
    if train >= paper_skill_mean(record["robot"], record["skill"]):
        stage = f"the trained objects reach the paper's mean ({pct(train)}%), the test objects do not"
    elif scripted is None:
        stage = f"training falls short too: trained objects {pct(train)}% (trained from scratch)"
    else:
        stage = (
            f"training falls short too: PPO took the trained objects from the scripted demonstrations' "
            f"{pct(scripted)}% to {pct(train)}%"
        )
    return f"{stage}; weakest test objects: " + ", ".join(f"{i} {pct(rate)}%" for i, rate in weakest)


def merged_records(path: Path, new: list[dict]) -> list[dict]:
    """`new` over the records already in `path` (earlier runs of other rows), in catalog order."""
    old = read_json(path) if path.is_file() else []
    by_row = {(r["category"], r["skill"]): r for r in [*old, *new]}
    return [by_row[row] for row in rows() if row in by_row]


def test_success(records: list[dict]) -> dict[tuple[str, str, str], float]:
    """(robot, object id, skill) -> success of the finished rows on their test objects: the paper tables come
    from the same rows as the per-row table, also those an earlier sweep trained under another --runs."""
    return {
        (r["robot"], object_id, r["skill"]): rate
        for r in records
        for object_id, rate in r["test_object_success"].items()
    }


def every_robots_records(root: Path) -> list[dict]:
    """The finished rows of every robot whose sweep writes to `root/<robot>` (`make teachers`' layout)."""
    files = [root / robot / f"teachers_{robot}.json" for robot in ROBOTS]
    return [record for path in files if path.is_file() for record in read_json(path)]


def rows_markdown(records: list[dict], total: int) -> str:
    lines = [
        f"{len(records)} of {total} rows finished. Success (%) over the category's test objects (not trained "
        "on), over the trained train objects, and of the warm start's scripted demonstrations on them.",
        "",
        "| category | skill | test success | train success | scripted | test / trained objects | samples "
        "| wall min |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    lines += [
        f"| {r['category']} | {r['skill']} | {pct(r['test_success'])} | {pct(r['train_success'])} | "
        f"{pct(r['scripted_success'])} | {r['test_objects']} / {r['trained_objects']} | {r['samples']:,} "
        f"| {r['wall_minutes']} |"
        for r in records
    ]
    below = [r for r in records if r["test_success"] < paper_skill_mean(r["robot"], r["skill"])]
    lines += ["", f"Rows below the paper's mean for their skill ({len(below)}):", ""]
    lines += [
        f"- {r['category']} {r['skill']}: {pct(r['test_success'])}% vs the paper's "
        f"{pct(paper_skill_mean(r['robot'], r['skill']))}%; {diagnosis(r)}"
        for r in below
    ]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--robot", default="g1", choices=sorted(ROBOTS))
    parser.add_argument("--runs", type=Path, default=Path("outputs/teachers"))
    parser.add_argument("--out", type=Path, default=None, help="default: outputs/teachers/tables/<robot>")
    parser.add_argument("--categories", nargs="+", default=None)
    parser.add_argument("--skills", nargs="+", default=None)
    parser.add_argument("--skill-iterations", nargs="+", default=[], metavar="SKILL:N")
    parser.add_argument(
        "--test-episodes",
        type=int,
        default=0,
        metavar="N",
        help="at least N evaluation episodes over each row's test objects (more per object where it has few)",
    )
    # Hydra overrides for every row (conf/rl.yaml), anywhere on the line: category and skill names hold no
    # '=', so `--categories box rl.ppo.max_iterations=300` does not read the override as a category.
    argv = sys.argv[1:] if argv is None else argv
    hydra_overrides = [a for a in argv if "=" in a and not a.startswith("-")]
    args = parser.parse_args([a for a in argv if a not in hydra_overrides])
    args.out = args.out or Path("outputs/teachers/tables", args.robot)
    for category in args.categories or []:
        check_choice(category, CATEGORIES, "category")
    for skill in args.skills or []:
        check_choice(skill, ALL_SKILLS, "skill")
    if args.test_episodes < 0:
        raise InputError(f"--test-episodes {args.test_episodes}: expected N >= 0")
    per_skill = dict(skill_iterations(text) for text in args.skill_iterations)
    todo = rows(args.categories, args.skills)
    if not todo:  # only a category list can lack every skill asked for
        offered = sorted({skill for _, skill in rows(args.categories)})
        raise InputError(
            f"--skills {' '.join(args.skills)} selects no row of --categories {' '.join(args.categories)}, "
            f"whose skills are {', '.join(offered)}"
        )
    check_writable(args.runs, "--runs")
    check_writable(args.out, "--out")
    overrides = [
        row_overrides(args.robot, c, s, args.runs, hydra_overrides, per_skill.get(s), args.test_episodes)
        for c, s in todo
    ]
    # every row, and every run directory a row resumes, checked before the first one trains
    configs = [checked_row_config(o) for o in overrides]
    checks = [check_run(cfg) for cfg in configs]
    rows_file = args.out / f"teachers_{args.robot}.json"
    recorded = {(r["category"], r["skill"]): r for r in (read_json(rows_file) if rows_file.is_file() else [])}
    records = []
    for k, ((category, skill), row_args, cfg, check) in enumerate(
        zip(todo, overrides, configs, checks, strict=True)
    ):
        run_dir = Path(cfg.run_dir)
        print(f"[row {k + 1}/{len(todo)}] {args.robot} {category} {skill}: {run_dir}", flush=True)
        command = "python -m mobilemani_rl.rl.train " + " ".join(row_args)
        earlier, evaluated = recorded.get((category, skill)), evaluation_file(run_dir) is not None
        if not evaluated and earlier is not None and earlier["command"] == command:
            # a row finished on another machine (or before its runs were deleted): its record stands
            print(f"  kept: {rows_file} records it by the same command", flush=True)
            records.append(earlier)
        else:
            if check.grown or not evaluated:
                run_row(cfg)
            records.append(row_record(args.robot, category, skill, run_dir, command))
        args.out.mkdir(parents=True, exist_ok=True)
        everything = merged_records(rows_file, records)
        write_json_atomic(rows_file, everything)
        (args.out / f"teachers_{args.robot}.md").write_text(rows_markdown(everything, len(rows())))
        write_tables(test_success(everything), args.out)
        if args.out.name == args.robot:  # `TEACHERS_OUT/<robot>`: the paper tables with every robot's column
            write_tables(test_success(every_robots_records(args.out.parent)), args.out.parent)


if __name__ == "__main__":
    entry_point(main)()

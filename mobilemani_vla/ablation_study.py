"""The paper's VLA ablation study (Section 4.2) at one scale, as one resumable command:

    python -m mobilemani_vla.ablation_study [--scale cpu|paper] [--minutes 150] [--rows ROW ...]
        [--episodes 2] [--workers 2] [--train OVERRIDE ...] [--eval OVERRIDE ...] [--tables DIR]
    make ablation [ABLATION_ARGS="--minutes 120"]

Each call does the study's next unfinished work, in order, until all of it is done or `--minutes` are spent:
a row's training (`python -m mobilemani_vla.train +experiment=<row>` with the scale's overrides and then
`--train`'s, in a piece that ends before the deadline), then its closed-loop evaluation
(`python -m mobilemani_vla.eval.evaluate eval/protocol=ablation name=<row>`, `--episodes` per combination,
then `--eval`'s overrides). The order follows what each table needs first: the main row on unseen objects in
unseen scenes, the image rows that answer whether depth helps, the main row on the three other object x scene
splits, the state rows, the last image row, then the stock LeRobot baselines of the model comparison (ACT,
Diffusion Policy, SmolVLA from scratch: `python -m mobilemani_vla.lerobot_train`, lerobot-train on the same
dataset, the same inputs as the main row, then the same evaluation with `eval/policy=lerobot`; their training
is stopped at the deadline and resumes from its last checkpoint, saved every 1/60 of its steps, the older ones
deleted). Training and evaluation resume where a call stopped, so rerunning
the same command continues the study; a training piece starts only with `MIN_PIECE_MINUTES` left. A row whose
evaluations are all in the results directory (`--eval output_dir=DIR`; docs/results/ablation/eval holds ours)
is not trained again, checkpoint or not. Every call ends by writing the paper's VLA tables (`make tables`'
`vla/`) from every result so far.

Scales: `cpu` adds `vla/model=cpu vla/train=ablation_cpu` (2 CPU cores; docs/results/ablation.md) and trains
the baselines with `--preset=cpu` for about the main row's training time; `paper` keeps the experiments' own
settings (PaliGemma-2 3B, 160K steps at batch 120: a GPU job) and trains the baselines for as many, with
LeRobot's own sizes. The seen splits are
subsampled to about the size of the unseen one (264 combinations): each seen object in the first of its
training rooms (272 combinations), each unseen object in the first four (264).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path

from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.errors import InputError, MissingFileError
from mobilemani_rl.utils.io import check_writable
from mobilemani_vla.checkpoint import checkpoint_dir
from mobilemani_vla.config import VLACfg, compose_vla_cfg
from mobilemani_vla.data.dataset import open_metadata
from mobilemani_vla.eval.config import EvalCfg, compose_eval_cfg
from mobilemani_vla.eval.evaluate import evaluate, run_dir
from mobilemani_vla.eval.results import finished, read_records
from mobilemani_vla.eval.tables import write_tables
from mobilemani_vla.lerobot_presets import merge_flags
from mobilemani_vla.lerobot_train import check_arguments, given, keep_last_checkpoint, trained_step
from mobilemani_vla.train import train

MAIN_ROW = "ablation_image_all"
SCALES = {"cpu": ["vla/model=cpu", "vla/train=ablation_cpu"], "paper": []}
# Each split's subset overrides: the seen ones subsampled to about the unseen one's 264 combinations.
SPLITS = {
    "unseen_unseen": [],
    "seen_seen": ["subset.scenes_per_object=1"],
    "seen_unseen": ["subset.scenes_per_object=1"],
    "unseen_seen": ["subset.scenes_per_object=4"],
}
# (row, the splits it is evaluated on), in the order the study runs them.
JOBS = [
    (MAIN_ROW, ["unseen_unseen"]),
    ("ablation_image_head_rgbd", ["unseen_unseen"]),
    ("ablation_image_head_rgb", ["unseen_unseen"]),
    (MAIN_ROW, ["seen_seen", "seen_unseen", "unseen_seen"]),
    ("ablation_state_none", ["unseen_unseen"]),
    ("ablation_state_grasp_point", ["unseen_unseen"]),
    ("ablation_state_goal_point", ["unseen_unseen"]),
    ("ablation_image_head_wrist_rgb", ["unseen_unseen"]),
    ("ablation_act", ["unseen_unseen"]),
    ("ablation_diffusion", ["unseen_unseen"]),
    ("ablation_smolvla", ["unseen_unseen"]),
]
ROWS = list(dict.fromkeys(row for row, _ in JOBS))
# The model comparison's stock LeRobot policies: row -> policy type.
BASELINES = {"ablation_act": "act", "ablation_diffusion": "diffusion", "ablation_smolvla": "smolvla"}
# lerobot-train's settings at each scale, beside the dataset, the run directory and the save frequency, and
# each policy type's steps: at CPU scale, about the main row's training time on 2 cores from each policy's
# measured rate (docs/results/ablation.md); at the paper's, its VLA steps and batch.
BASELINE_TRAINING = {
    "cpu": (["--preset=cpu", "--batch_size=32"], {"act": 5000, "diffusion": 6000, "smolvla": 9000}),
    "paper": (["--batch_size=120"], dict.fromkeys(BASELINES.values(), 160000)),
}
# A baseline's inputs are LeRobot's: every camera stream (the main row's four) and observation.state, the main
# row's wrist pose with the gripper joint. Saves per run: what a stop at the deadline can lose.
SAVES_PER_RUN = 60
MIN_PIECE_MINUTES = 5.0
# What a training call spends outside its piece: loading the data and the model, the closing diagnostics and
# checkpoint.
TRAIN_OVERHEAD_MINUTES = 3.0


@dataclass
class Budget:
    deadline: float  # time.monotonic() at which the call's minutes are spent

    @classmethod
    def of(cls, minutes: float) -> Budget:
        return cls(time.monotonic() + 60 * minutes)

    def minutes_left(self) -> float:
        return (self.deadline - time.monotonic()) / 60


def row_training(row: str, overrides: list[str]) -> VLACfg:
    return compose_vla_cfg([f"+experiment={row}", *overrides])


def final_checkpoint(cfg: VLACfg) -> Path:
    return checkpoint_dir(Path(cfg.train.output_dir), cfg.train.steps)


def split_evaluation(
    row: str, split: str, checkpoint: Path, args: argparse.Namespace, policy: str = "vla"
) -> EvalCfg:
    return compose_eval_cfg(
        [
            f"eval/policy={policy}",
            "eval/protocol=ablation",
            f"eval/split={split}",
            *SPLITS[split],
            f"name={row}",
            f"policy.checkpoint={checkpoint}",
            f"subset.episodes={args.episodes}",
            f"workers={args.workers}",
            *args.eval,
        ]
    )


def evaluated(cfg: EvalCfg) -> bool:
    path = run_dir(cfg) / f"{cfg.split_name}.jsonl"
    return finished(path, read_records(path))


def train_row(cfg: VLACfg, budget: Budget) -> bool:
    """Train the row until its last step or the budget; returns whether its last checkpoint exists."""
    if final_checkpoint(cfg).is_dir():
        return True
    piece = budget.minutes_left() - TRAIN_OVERHEAD_MINUTES
    if piece < MIN_PIECE_MINUTES:
        return False
    limit = cfg.train.piece_minutes
    cfg.train.piece_minutes = piece if limit <= 0 else min(limit, piece)
    print(
        f"== {cfg.name}: training to step {cfg.train.steps} (this piece: {cfg.train.piece_minutes:.0f} min)"
    )
    train(cfg)
    return final_checkpoint(cfg).is_dir()


def baseline_flags(row: str, dataset: VLACfg, args: argparse.Namespace) -> list[str]:
    """lerobot-train's arguments for a baseline row, on the dataset the VLA rows train on."""
    scale_flags, steps_of = BASELINE_TRAINING[args.scale]
    flags = [
        f"--policy.type={BASELINES[row]}",
        f"--dataset.root={dataset.data.root}",
        f"--dataset.repo_id={dataset.data.repo_id}",
        f"--output_dir={args.lerobot_out / row}",
        "--log_freq=100",
        *scale_flags,
        f"--steps={steps_of[BASELINES[row]]}",
    ]
    extra = [f"--{flag}" for flag in args.lerobot]
    steps = int(given([*flags, *extra]).steps)
    return merge_flags([*flags, f"--save_freq={max(1, steps // SAVES_PER_RUN)}"], extra)


def baseline_checkpoint(flags: list[str]) -> Path:
    """The pretrained_model directory of the run's last step (lerobot-train's step naming)."""
    from lerobot.common.train_utils import get_step_identifier  # lerobot's policies load with it
    from lerobot.utils.constants import PRETRAINED_MODEL_DIR

    run = given(flags)
    step = get_step_identifier(int(run.steps), int(run.steps))
    return Path(run.output_dir) / "checkpoints" / step / PRETRAINED_MODEL_DIR


def train_baseline(row: str, flags: list[str], budget: Budget) -> bool:
    """lerobot-train on the baseline's flags until its last step or the budget (stopped there; the next call
    resumes it from its last checkpoint); returns whether its last checkpoint exists."""
    if baseline_checkpoint(flags).is_dir():
        return True
    piece = budget.minutes_left() - 1
    if piece < MIN_PIECE_MINUTES:
        return False
    settings = given(flags)
    run = Path(settings.output_dir)
    start = trained_step(run)
    print(
        f"== {row}: training to step {settings.steps} from step {start} (this piece: {piece:.0f} min)",
        flush=True,
    )
    command = [sys.executable, "-m", "mobilemani_vla.lerobot_train", *flags]
    try:
        done = subprocess.run(command, timeout=60 * piece, env=os.environ | {"HF_HUB_OFFLINE": "1"})
    except subprocess.TimeoutExpired:
        print(f"== {row}: stopped at the deadline, last checkpoint at step {trained_step(run)}", flush=True)
    else:
        if done.returncode:
            raise RuntimeError(f"{row}: lerobot-train exited with {done.returncode} (its output is above)")
    keep_last_checkpoint(run)
    return baseline_checkpoint(flags).is_dir()


def evaluate_split(cfg: EvalCfg, budget: Budget) -> bool:
    """Evaluate one split until its last episode or the budget; returns whether it is complete."""
    if evaluated(cfg):
        return True
    if (left := budget.minutes_left()) < 1:
        return False
    cfg.piece_minutes = left
    print(f"== {cfg.name}: evaluating on {cfg.split_name}")
    evaluate(cfg)
    return evaluated(cfg)


def check_training_data(cfgs: list[VLACfg]) -> None:
    """Before anything runs: the dataset of every row still to train exists and has the row's inputs."""
    for cfg in cfgs:
        if not (Path(cfg.data.root) / "meta").is_dir():
            raise MissingFileError(
                f"no ablation dataset at {cfg.data.root} (data.root): make it with `make data ROBOT=g1 "
                'PRESET=ablation DATA_ARGS="data_dir=outputs/data/ablation"` (docs/usage.md, "The ablation '
                'dataset") or name another with --train data.root=<dir>'
            )
        open_metadata(cfg)


Job = tuple[Callable[[Budget], bool], list[EvalCfg]]  # (train within a budget: whether done, evaluations)


def study_jobs(args: argparse.Namespace) -> list[Job]:
    """The unfinished jobs of `args.rows` in the study's order, every config composed and checked."""
    overrides = [*SCALES[args.scale], *args.train]
    dataset = row_training(MAIN_ROW, overrides)  # the baselines train on the main row's dataset
    trainings = {row: row_training(row, overrides) for row in args.rows if row not in BASELINES}
    baselines = {row: baseline_flags(row, dataset, args) for row in args.rows if row in BASELINES}
    jobs: list[Job] = []
    to_train: set[str] = set()
    for row, splits in JOBS:
        if row in trainings:
            cfg = trainings[row]
            evaluations = [split_evaluation(row, s, final_checkpoint(cfg), args) for s in splits]
            train_job = partial(train_row, cfg)
        elif row in baselines:
            checkpoint = baseline_checkpoint(baselines[row])
            evaluations = [split_evaluation(row, s, checkpoint, args, "lerobot") for s in splits]
            train_job = partial(train_baseline, row, baselines[row])
        else:
            continue
        # Evaluations already recorded (kept with the results, e.g. committed) need no checkpoint: their
        # row is trained again only for a split it still lacks.
        if not all(evaluated(cfg) for cfg in evaluations):
            jobs.append((train_job, evaluations))
            to_train.add(row)
    untrained = [
        cfg for row, cfg in trainings.items() if row in to_train and not final_checkpoint(cfg).is_dir()
    ]
    untrained_baselines = [
        flags
        for row, flags in baselines.items()
        if row in to_train and not baseline_checkpoint(flags).is_dir()
    ]
    check_training_data([*untrained, dataset] if untrained_baselines else untrained)
    for flags in untrained_baselines:
        check_arguments(flags)
    return jobs


def run_study(args: argparse.Namespace) -> bool:
    """The study's unfinished jobs among `args.rows`, in order, within `args.minutes`; returns whether every
    one of them is done."""
    budget = Budget.of(args.minutes)
    for train_job, evaluations in study_jobs(args):
        if not train_job(budget):
            return False
        if not all(evaluate_split(cfg, budget) for cfg in evaluations):  # stops at the first unfinished
            return False
    return True


@entry_point
def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--scale", choices=sorted(SCALES), default="cpu")
    parser.add_argument("--minutes", type=float, default=150.0, help="this call's time budget")
    parser.add_argument(
        "--rows", nargs="+", default=ROWS, help=f"rows to run (default all: {' '.join(ROWS)})"
    )
    parser.add_argument("--episodes", type=int, default=2, help="evaluation episodes per combination")
    parser.add_argument("--workers", type=int, default=2, help="evaluation worker processes")
    parser.add_argument("--train", nargs="*", default=[], help="more training overrides (every row)")
    parser.add_argument("--eval", nargs="*", default=[], help="more evaluation overrides (every split)")
    parser.add_argument(
        "--lerobot",
        nargs="*",
        default=[],
        help="more lerobot-train flags (every baseline) as key=value, e.g. policy.chunk_size=8",
    )
    parser.add_argument(
        "--lerobot-out", type=Path, default=Path("outputs/lerobot/g1"), help="where baselines train"
    )
    parser.add_argument("--tables", type=Path, default=Path("outputs/tables/vla"), help="where tables go")
    args = parser.parse_args()
    if unknown := sorted(set(args.rows) - set(ROWS)):
        raise InputError(f"--rows: unknown {', '.join(unknown)}; choose among {', '.join(ROWS)}")
    if args.minutes <= 0 or args.episodes < 1:
        raise InputError("--minutes must be > 0 and --episodes >= 1")
    check_writable(args.tables, "--tables")
    complete = run_study(args)
    results = Path(compose_eval_cfg(args.eval).output_dir)
    write_tables(results, args.tables, MAIN_ROW, MAIN_ROW)
    if complete:
        print(f"the study's rows {', '.join(args.rows)} are trained and evaluated")
    else:
        print(f"--minutes {args.minutes:g} spent: the same command continues the study")


if __name__ == "__main__":
    main()

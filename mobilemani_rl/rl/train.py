"""Train a PPO teacher for one (robot, object, skill), or for a whole category (multi-object mode):

    python -m mobilemani_rl.rl.train robot=g1 task.object=test/box task.skill=open [rl/ppo=paper]
    python -m mobilemani_rl.rl.train robot=g1 task.object=laptop task.skill=open objects_per_policy=8

Rerunning the same command resumes from the run directory's newest checkpoint with its saved config
(or, before PPO's first checkpoint, from the finished warm start); a finished run
(result.json present) is left as it is, unless asked for more iterations (`rl.ppo.max_iterations`), which it
goes on to from its newest checkpoint. While a process trains a run directory it holds `train.lock` there,
so a second one on the same directory stops at once instead of writing the same checkpoints. A run_dir that
cannot be written (a file in the way, a read-only file system) stops before anything is built.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import hydra
from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.rl.config import PpoCfg, RLCfg
from mobilemani_rl.rl.eval import evaluate
from mobilemani_rl.rl.factory import build_runner
from mobilemani_rl.rl.run_dir import (
    CURVE,
    RESULT,
    WARM_START,
    WARM_START_CHECKPOINT,
    ConfigRules,
    RunCheck,
    check_config,
    checkpoints,
    is_complete,
    latest_checkpoint,
    save_or_check_config,
)
from mobilemani_rl.rl.runner import MobileManiRunner
from mobilemani_rl.rl.warm_start import warm_start
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.io import check_writable, write_json_atomic
from mobilemani_rl.utils.writer_lock import TRAIN_LOCK, WriterLock, busy

# where a run computes, not what it learns: a resumed run may change them (each env steps alone, so the
# physics thread count does not change a trajectory)
PLACEMENT_KEYS = ("rl.ppo.device", "rl.ppo.torch_threads", "rl.ppo.update_threads", "env.physics.nthread")
RUN_RULES = ConfigRules(
    keys=("task", "env", "rl"),
    defaults=OmegaConf.to_container(OmegaConf.structured(RLCfg)),
    placement=PLACEMENT_KEYS,
    # a run may be given more iterations: PPO has no schedule tied to their count (the learning rate adapts
    # to the KL divergence), so going on from iteration N is the same run as one asked for more at first
    budgets=("rl.ppo.max_iterations",),
)


def check_run(cfg: DictConfig) -> RunCheck:
    """How `cfg` stands against its run directory, writing nothing; ConfigMismatchError if it cannot go on."""
    return check_config(Path(cfg.run_dir), cfg, RUN_RULES)


def load_newest_readable(runner: MobileManiRunner, run_dir: Path) -> Path | None:
    """Load the newest checkpoint that reads back; an unreadable one (a disk fault, a copy cut short) is named
    and skipped, so the run continues from the previous good one."""
    for path in checkpoints(run_dir):
        try:
            runner.load(str(path))
            return path
        except ValueError as err:
            print(f"skipping an unreadable checkpoint: {err}")
    return None


def train(cfg: DictConfig) -> Path:
    ppo = to_dataclass(cfg, RLCfg).check().rl.ppo  # before anything is written
    run_dir = check_writable(cfg.run_dir, "run_dir")
    with WriterLock(run_dir / TRAIN_LOCK, busy("training run", run_dir, "run_dir")):
        # first: a finished run asked for other settings is an error, for more iterations it goes on
        save_or_check_config(run_dir, cfg, RUN_RULES)
        if is_complete(run_dir):
            print(f"{run_dir} is complete ({RESULT} exists); nothing to do")
        else:
            run_ppo(cfg, ppo, run_dir)
    return run_dir


def run_ppo(cfg: DictConfig, ppo: PpoCfg, run_dir: Path) -> None:
    """The warm start and PPO of a run directory whose config is saved, from wherever it stopped; its
    curve and `result.json` last."""
    runner = build_runner(cfg, run_dir)
    wall = time.time()
    start = 0
    if (checkpoint := load_newest_readable(runner, run_dir)) is not None:
        start = runner.current_learning_iteration + 1
        runner.current_learning_iteration = start
        runner.resume_curve(start)
        print(f"resuming {run_dir} from {checkpoint.name} (iteration {start} of {ppo.max_iterations})")
    elif (warm := run_dir / WARM_START_CHECKPOINT).exists():
        runner.load(str(warm))
        print(f"resuming {run_dir} from its finished warm start ({WARM_START_CHECKPOINT})")
    elif ppo.warm_start.episodes > 0:
        print(
            f"warm start: cloning the scripted policy before {ppo.max_iterations} PPO iterations "
            "(rl.ppo.warm_start.episodes=0 trains from scratch)"
        )
        info = warm_start(
            runner.alg.actor,
            runner.alg.critic,
            runner.env.env,
            ppo.warm_start,
            ppo.gamma,
            fit_threads=ppo.update_threads,
        )
        write_json_atomic(run_dir / WARM_START, {**info, "seconds": round(time.time() - wall, 1)})
        # last and atomic: only a finished warm start is kept, and a rerun starts PPO from it
        runner.save(str(warm))
        print(
            f"warm start: cloned {info['episodes']} scripted episodes ({info['steps']} steps, "
            f"scripted success {info['scripted_success']:.2f}), "
            f"actor loss {info['actor_loss'][0]:.4f} -> {info['actor_loss'][1]:.4f}"
        )
    remaining = ppo.max_iterations - start
    if remaining > 0:
        runner.learn(num_learning_iterations=remaining, init_at_random_ep_len=ppo.init_at_random_ep_len)
    curve = runner.logger.curve
    write_json_atomic(run_dir / CURVE, curve)
    write_json_atomic(
        run_dir / RESULT,
        {
            "iterations": ppo.max_iterations,
            "samples": ppo.max_iterations * ppo.num_envs * ppo.num_steps_per_env,
            "train_success": last_measured_success(curve),
            "wall_seconds_this_session": round(time.time() - wall, 1),
            "checkpoint": str(latest_checkpoint(run_dir)),
        },
    )


def last_measured_success(curve: list[dict]) -> float | None:
    """The newest finite success of a training curve: an iteration in which no episode ended logs NaN."""
    measured = [
        row["success"]
        for row in curve
        if isinstance(row.get("success"), float) and math.isfinite(row["success"])
    ]
    return measured[-1] if measured else None


@hydra.main(config_path="../../conf", config_name="rl", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    run_dir = train(cfg)
    eval_episodes = to_dataclass(cfg, RLCfg).eval_episodes
    if eval_episodes > 0:
        result = evaluate(latest_checkpoint(run_dir), eval_episodes, seed=1000)
        trained = sum(r["trained"] for r in result["objects"].values())
        by_split = ", ".join(
            f"{split} {rate:.3f}" for split, rate in sorted(result["success_by_split"].items())
        )
        print(
            f"{run_dir}: success {result['success_rate']:.3f} on the {trained} trained object(s), "
            f"{eval_episodes} episodes each "
            f"(all {len(result['objects'])} evaluated objects by split: {by_split})"
        )


if __name__ == "__main__":
    main()

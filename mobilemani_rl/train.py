"""Train a PPO teacher for one (robot, object, skill), or for a whole category (multi-object mode):

    python -m mobilemani_rl.train robot=g1 task.object=test/box task.skill=open [rl/ppo=paper]
    python -m mobilemani_rl.train robot=g1 task.object=laptop task.skill=open objects_per_policy=8

Rerunning the same command resumes from the run directory's newest checkpoint with its saved config; a
finished run (result.json present) is left as it is.
"""

from __future__ import annotations

import time
from pathlib import Path

import hydra
import torch
from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.assets.objects import CATEGORIES, catalog_ids
from mobilemani_rl.envs.config import EnvCfg, env_cfg_from_hydra
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.multi_object import MultiObjectEnv
from mobilemani_rl.envs.vecenv import RslRlVecEnv
from mobilemani_rl.rl.config import PpoCfg, rsl_rl_train_cfg
from mobilemani_rl.rl.run_dir import (
    CURVE,
    RESULT,
    is_complete,
    latest_checkpoint,
    save_or_check_config,
    write_json_atomic,
)
from mobilemani_rl.rl.runner import MobileManiRunner

RUN_KEYS = ("task", "env", "rl")


def ppo_cfg_from_hydra(cfg: DictConfig) -> PpoCfg:
    return OmegaConf.to_object(OmegaConf.merge(OmegaConf.structured(PpoCfg), cfg.rl.ppo))


def policy_objects(task_object: str, max_objects: int) -> list[str] | None:
    """A category name selects multi-object mode over its train objects; an object id trains one object."""
    if task_object not in CATEGORIES:
        return None
    return catalog_ids(task_object, "train")[:max_objects]


def make_env(env_cfg: EnvCfg, max_objects: int) -> MobileManiEnv | MultiObjectEnv:
    objects = policy_objects(env_cfg.task.object, max_objects)
    return MobileManiEnv(env_cfg) if objects is None else MultiObjectEnv(env_cfg, objects)


def build_runner(cfg: DictConfig, run_dir: Path | None, num_envs: int | None = None,
                 env: MobileManiEnv | MultiObjectEnv | None = None) -> MobileManiRunner:
    """Env + rsl-rl runner for a composed config (run_dir None: no logging, e.g. for evaluation)."""
    ppo = ppo_cfg_from_hydra(cfg)
    if ppo.torch_threads:
        torch.set_num_threads(ppo.torch_threads)
    torch.manual_seed(ppo.seed)
    if env is None:
        env_cfg = env_cfg_from_hydra(cfg)
        env_cfg.num_envs, env_cfg.seed = num_envs or ppo.num_envs, ppo.seed
        env = make_env(env_cfg, cfg.objects_per_policy)
    env_cfg = env.cfg
    env = RslRlVecEnv(env)
    logger = cfg.logger if cfg.logger == "tensorboard" else {"class_name": "WandbLogWriter",
                                                              "project_name": cfg.wandb_project}
    run_name = f"{env_cfg.task.robot}/{env_cfg.task.object}/{env_cfg.task.skill}"
    train_cfg = rsl_rl_train_cfg(ppo, logger, run_name)
    return MobileManiRunner(env, train_cfg, None if run_dir is None else str(run_dir), ppo.max_iterations)


def train(cfg: DictConfig) -> Path:
    run_dir = Path(cfg.run_dir)
    if is_complete(run_dir):
        print(f"{run_dir} is complete ({RESULT} exists); nothing to do")
        return run_dir
    save_or_check_config(run_dir, cfg, RUN_KEYS)
    ppo = ppo_cfg_from_hydra(cfg)
    runner = build_runner(cfg, run_dir)
    start = 0
    if (checkpoint := latest_checkpoint(run_dir)) is not None:
        runner.load(str(checkpoint))
        start = runner.current_learning_iteration + 1
        runner.current_learning_iteration = start
        print(f"resuming {run_dir} from {checkpoint.name} (iteration {start} of {ppo.max_iterations})")
    wall = time.time()
    remaining = ppo.max_iterations - start
    if remaining > 0:
        runner.learn(num_learning_iterations=remaining, init_at_random_ep_len=ppo.init_at_random_ep_len)
    curve = runner.logger.curve
    previous = run_dir / CURVE
    if start and previous.exists():
        curve = OmegaConf.to_container(OmegaConf.load(previous)) + curve
    write_json_atomic(run_dir / CURVE, curve)
    last = curve[-1] if curve else {}
    write_json_atomic(run_dir / RESULT, {
        "iterations": ppo.max_iterations, "samples": ppo.max_iterations * ppo.num_envs * ppo.num_steps_per_env,
        "train_success": last.get("success"), "wall_seconds_this_session": round(time.time() - wall, 1),
        "checkpoint": str(latest_checkpoint(run_dir)),
    })
    return run_dir


@hydra.main(config_path="../conf", config_name="rl", version_base="1.3")
def main(cfg: DictConfig) -> None:
    train(cfg)


if __name__ == "__main__":
    main()

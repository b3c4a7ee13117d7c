"""Build the env and the rsl-rl runner of a composed RL config (shared by training and evaluation)."""

from __future__ import annotations

from pathlib import Path

import torch
from omegaconf import DictConfig

from mobilemani_rl.assets.objects import CATEGORIES, catalog_ids
from mobilemani_rl.envs.batched import BatchedEnv
from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.multi_object import MultiObjectEnv
from mobilemani_rl.envs.vecenv import RslRlVecEnv
from mobilemani_rl.rl.config import RLCfg, rsl_rl_train_cfg
from mobilemani_rl.rl.runner import MobileManiRunner
from mobilemani_rl.utils.config_store import to_dataclass


def policy_objects(task_object: str, max_objects: int) -> list[str] | None:
    """A category name selects multi-object mode over its train objects; an object id trains one object."""
    if task_object not in CATEGORIES:
        return None
    return catalog_ids(task_object, "train")[:max_objects]


def make_env(env_cfg: EnvCfg, max_objects: int) -> BatchedEnv:
    objects = policy_objects(env_cfg.task.object, max_objects)
    return MobileManiEnv(env_cfg) if objects is None else MultiObjectEnv(env_cfg, objects)


def build_runner(
    cfg: DictConfig,
    run_dir: Path | None,
    num_envs: int | None = None,
    env: BatchedEnv | None = None,
    device: str | None = None,
) -> MobileManiRunner:
    """Env + rsl-rl runner for a composed config or a run's saved one (run_dir None: no logging, e.g. for
    evaluation; device None: the config's rl.ppo.device)."""
    run = to_dataclass(cfg, RLCfg)
    ppo = run.rl.ppo
    if ppo.torch_threads:
        torch.set_num_threads(ppo.torch_threads)
    torch.manual_seed(ppo.seed)
    if env is None:
        env_cfg = run.env_cfg()
        env_cfg.num_envs, env_cfg.seed = num_envs or ppo.num_envs, ppo.seed
        env = make_env(env_cfg, run.objects_per_policy)
    env_cfg = env.cfg
    device = device or ppo.device
    env = RslRlVecEnv(env, device)
    logger = (
        run.logger
        if run.logger == "tensorboard"
        else {"class_name": "WandbLogWriter", "project_name": run.wandb_project}
    )
    run_name = f"{env_cfg.task.robot}/{env_cfg.task.object}/{env_cfg.task.skill}"
    train_cfg = rsl_rl_train_cfg(ppo, logger, run_name)
    return MobileManiRunner(
        env,
        train_cfg,
        None if run_dir is None else str(run_dir),
        ppo.max_iterations,
        update_threads=ppo.update_threads,
        device=device,
    )

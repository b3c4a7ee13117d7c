"""Build the env and the rsl-rl runner of a composed RL config (shared by training and evaluation)."""

from __future__ import annotations

from pathlib import Path

import torch
from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.assets.objects import CATEGORIES, catalog_ids
from mobilemani_rl.envs.batched import BatchedEnv
from mobilemani_rl.envs.config import EnvCfg, env_cfg_from_hydra
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.multi_object import MultiObjectEnv
from mobilemani_rl.envs.vecenv import RslRlVecEnv
from mobilemani_rl.rl.config import PpoCfg, rsl_rl_train_cfg
from mobilemani_rl.rl.runner import MobileManiRunner


def ppo_cfg_from_hydra(cfg: DictConfig) -> PpoCfg:
    return OmegaConf.to_object(OmegaConf.merge(OmegaConf.structured(PpoCfg), cfg.rl.ppo))


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
) -> MobileManiRunner:
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
    logger = (
        cfg.logger
        if cfg.logger == "tensorboard"
        else {"class_name": "WandbLogWriter", "project_name": cfg.wandb_project}
    )
    run_name = f"{env_cfg.task.robot}/{env_cfg.task.object}/{env_cfg.task.skill}"
    train_cfg = rsl_rl_train_cfg(ppo, logger, run_name)
    return MobileManiRunner(env, train_cfg, None if run_dir is None else str(run_dir), ppo.max_iterations)

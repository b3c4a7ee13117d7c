"""Several objects of one category in one batch of envs: a single policy per (robot, category, skill).

Each object gets its own `MobileManiEnv` (its own compiled model and `mujoco.batch.Batch`; objects of a
category differ in structure, so they cannot share one model) holding a contiguous slice of the envs. The
composite has the same interface as `MobileManiEnv`, so the rsl-rl and Gymnasium adapters wrap it unchanged.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv, StepResult
from mobilemani_rl.utils.errors import InputError


class MultiObjectEnv:
    def __init__(self, cfg: EnvCfg, object_ids: list[str]) -> None:
        if cfg.num_envs < len(object_ids):
            raise InputError(f"{cfg.num_envs} envs cannot hold {len(object_ids)} objects; use more envs")
        self.cfg = cfg
        sizes = np.diff(np.linspace(0, cfg.num_envs, len(object_ids) + 1).astype(int))
        self.envs = [
            MobileManiEnv(
                dataclasses.replace(
                    cfg, num_envs=int(size), seed=cfg.seed + i, task=dataclasses.replace(cfg.task, object=oid)
                )
            )
            for i, (oid, size) in enumerate(zip(object_ids, sizes, strict=True))
        ]
        self.bounds = np.concatenate(([0], np.cumsum(sizes)))
        first = self.envs[0]
        self.num_envs, self.num_actions, self.num_obs = cfg.num_envs, first.num_actions, first.num_obs
        self.max_episode_length = first.max_episode_length
        self.obs: np.ndarray | None = None

    def _slices(self):
        return zip(self.envs, self.bounds[:-1], self.bounds[1:], strict=True)

    @property
    def episode_length_buf(self) -> np.ndarray:
        return np.concatenate([env.episode_length_buf for env in self.envs])

    @episode_length_buf.setter
    def episode_length_buf(self, value: np.ndarray) -> None:
        for env, lo, hi in self._slices():
            env.episode_length_buf[:] = value[lo:hi]

    def reset(self, seed: int | None = None) -> np.ndarray:
        self.obs = np.concatenate(
            [env.reset(None if seed is None else seed + i) for i, env in enumerate(self.envs)]
        )
        return self.obs

    def step(self, actions: np.ndarray) -> StepResult:
        parts = [env.step(actions[lo:hi]) for env, lo, hi in self._slices()]
        weights = np.diff(self.bounds) / self.num_envs
        log: dict[str, float | np.ndarray] = {}
        for key in parts[0].log:
            values = [p.log.get(key) for p in parts]
            if isinstance(values[0], float):
                log[key] = float(np.dot(weights, values))
        for key in {k for p in parts for k, v in p.log.items() if isinstance(v, np.ndarray)}:
            log[key] = np.concatenate([p.log[key] for p in parts if key in p.log])
        self.obs = np.concatenate([p.obs for p in parts])
        return StepResult(
            obs=self.obs,
            reward=np.concatenate([p.reward for p in parts]),
            terminated=np.concatenate([p.terminated for p in parts]),
            truncated=np.concatenate([p.truncated for p in parts]),
            success_flag=np.concatenate([p.success_flag for p in parts]),
            final_obs=np.concatenate([p.final_obs for p in parts]),
            done_ids=np.concatenate([p.done_ids + lo for p, lo in zip(parts, self.bounds[:-1], strict=True)]),
            reward_terms={
                k: np.concatenate([p.reward_terms[k] for p in parts]) for k in parts[0].reward_terms
            },
            log=log,
            nan_actions=np.concatenate([p.nan_actions for p in parts]),
        )

"""Adapters of a batched env (MobileManiEnv, MultiObjectEnv) to rsl-rl's `VecEnv` (TensorDict observations)
and Gymnasium's `VectorEnv`."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import torch
from gymnasium.vector import AutoresetMode
from rsl_rl.env import VecEnv
from tensordict import TensorDict

from mobilemani_rl.envs.batched import BatchedEnv


class RslRlVecEnv(VecEnv):
    """rsl-rl view: observations under group "policy" (policy = critic: no asymmetric critic);
    `time_outs` bootstraps."""

    def __init__(self, env: BatchedEnv, device: str = "cpu") -> None:
        self.env = env
        self.device = device
        self.num_envs = env.num_envs
        self.num_actions = env.num_actions
        self.max_episode_length = env.max_episode_length
        self.cfg = env.cfg
        if env.obs is None:
            env.reset()

    @property
    def episode_length_buf(self) -> torch.Tensor:
        return torch.from_numpy(self.env.episode_length_buf)

    @episode_length_buf.setter
    def episode_length_buf(self, value: torch.Tensor) -> None:
        # rsl-rl randomises episode lengths at start (init_at_random_ep_len); the time encoding is unaffected.
        # Assigned, not written into: a MultiObjectEnv's buffer is a property concatenating its parts
        # (a copy), and a lost write left all its episodes in step, so whole PPO iterations ended none
        # (success/reward NaN).
        self.env.episode_length_buf = value.cpu().numpy().astype(np.int64)

    def _observations(self, obs: np.ndarray) -> TensorDict:
        return TensorDict(
            {"policy": torch.from_numpy(obs).to(self.device)}, batch_size=[self.num_envs], device=self.device
        )

    def get_observations(self) -> TensorDict:
        return self._observations(self.env.obs)

    def step(self, actions: torch.Tensor | np.ndarray) -> tuple[TensorDict, torch.Tensor, torch.Tensor, dict]:
        # rsl-rl hands tensors; a numpy batch (GymVectorEnv's kind) goes to the env's own shape check as it is
        if isinstance(actions, torch.Tensor):
            actions = actions.detach().cpu().numpy()
        result = self.env.step(actions)
        dones = torch.from_numpy(result.terminated | result.truncated).to(self.device)
        extras = {
            "time_outs": torch.from_numpy(result.truncated).to(self.device),
            "log": {k: torch.as_tensor(v) for k, v in result.log.items()},
        }
        rewards = torch.from_numpy(result.reward.astype(np.float32)).to(self.device)
        return self._observations(result.obs), rewards, dones, extras


class GymVectorEnv(gym.vector.VectorEnv):
    """Gymnasium vector view with same-step autoreset: `infos["final_obs"]` holds ended episodes' last obs."""

    metadata: dict[str, Any] = {"autoreset_mode": AutoresetMode.SAME_STEP}

    def __init__(self, env: BatchedEnv) -> None:
        self.env = env
        self.num_envs = env.num_envs
        clip = env.cfg.obs_clip
        self.single_observation_space = gym.spaces.Box(-clip, clip, (env.num_obs,), np.float32)
        self.single_action_space = gym.spaces.Box(-1.0, 1.0, (env.num_actions,), np.float32)
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, self.num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, self.num_envs)

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[np.ndarray, dict]:
        return self.env.reset(seed=seed), {}

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict]:
        result = self.env.step(actions)
        done = np.zeros(self.num_envs, dtype=bool)
        done[result.done_ids] = True
        final_obs = np.full(self.num_envs, None, dtype=object)
        final_obs[result.done_ids] = list(result.final_obs)
        infos = {"final_obs": final_obs, "_final_obs": done, "success": result.success_flag}
        return result.obs, result.reward, result.terminated, result.truncated, infos

"""Rebuild a shard's model and put recorded states back into an MjData, for rendering and replay checks."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from omegaconf import OmegaConf

from mobilemani_data.shards import Episode, Shard
from mobilemani_rl.assets.objects import get_object
from mobilemani_rl.assets.robots import get_robot
from mobilemani_rl.assets.scenes import get_placement
from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.scene import build_scene

STATE_SPEC = mujoco.mjtState.mjSTATE_INTEGRATION


@dataclass
class ReplayErrors:
    """Largest absolute differences between replayed and recorded quantities."""

    kinematics: float  # world poses recomputed from each recorded state vs the recorded ones
    dynamics: (
        float  # state reached by stepping from each recorded state with the next control vs the next state
    )

    def worst(self) -> float:
        return max(self.kinematics, self.dynamics)


class Replayer:
    def __init__(self, shard: Shard) -> None:
        self.env_cfg: EnvCfg = OmegaConf.to_object(
            OmegaConf.merge(OmegaConf.structured(EnvCfg), OmegaConf.create(shard.header["env_cfg"]))
        )
        task = self.env_cfg.task
        placement = get_placement(task.scene) if task.scene else None
        self.model, self.index = build_scene(
            get_robot(task.robot),
            get_object(task.object),
            self.env_cfg.physics,
            self.env_cfg.reset,
            placement,
        )
        self.data = mujoco.MjData(self.model)
        if mujoco.mj_stateSize(self.model, STATE_SPEC) != shard.episodes[0].arrays["state"].shape[1]:
            raise ValueError(f"{shard.path}: recorded state size does not match the rebuilt model")

    def set_state(self, state: np.ndarray) -> mujoco.MjData:
        """The recorded state with every derived quantity (poses, cameras) recomputed."""
        mujoco.mj_setState(self.model, self.data, state, STATE_SPEC)
        mujoco.mj_forward(self.model, self.data)
        return self.data

    def check(self, episode: Episode) -> ReplayErrors:
        a, idx = episode.arrays, self.index
        kinematics = 0.0
        for t, state in enumerate(a["state"]):
            d = self.set_state(state)
            replayed = {
                "hand_pos": d.xpos[idx.hand_body],
                "hand_quat": d.xquat[idx.hand_body],
                "base_pos": d.xpos[idx.base_body],
                "base_quat": d.xquat[idx.base_body],
                "grasp_pos": d.site_xpos[idx.grasp_site],
                "palm_pos": d.site_xpos[idx.palm_site],
            }
            kinematics = max(kinematics, *(float(np.abs(v - a[k][t]).max()) for k, v in replayed.items()))
        return ReplayErrors(kinematics, self._dynamics(a["state"]))

    def _dynamics(self, states: np.ndarray) -> float:
        """Step each recorded state with the control applied after it, as the env's substeps did."""
        ctrl = slice(*_component(self.model, mujoco.mjtState.mjSTATE_CTRL))
        out = np.empty(states.shape[1])
        worst = 0.0
        for t in range(len(states) - 1):
            mujoco.mj_setState(self.model, self.data, states[t], STATE_SPEC)
            self.data.ctrl[:] = states[t + 1][ctrl]
            for _ in range(self.env_cfg.physics.substeps):
                mujoco.mj_step(self.model, self.data)
            mujoco.mj_getState(self.model, self.data, out, STATE_SPEC)
            worst = max(worst, float(np.abs(out - states[t + 1]).max()))
        return worst


def _component(model: mujoco.MjModel, component: mujoco.mjtState) -> tuple[int, int]:
    """[start, stop) of one component inside an mjSTATE_INTEGRATION vector (components are in bit order)."""
    start = sum(
        mujoco.mj_stateSize(model, 1 << b)
        for b in range(int(component).bit_length() - 1)
        if (1 << b) & int(STATE_SPEC)
    )
    return start, start + mujoco.mj_stateSize(model, component)

"""MobileManiVLA as an evaluation policy: its cameras and base-frame states in,
base-frame action chunks out."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from mobilemani_data import schema
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.utils.errors import InputError
from mobilemani_rl.utils.rotations import quat_apply, quat_conj
from mobilemani_vla.checkpoint import recorded_image_size, training_scale
from mobilemani_vla.eval.policies.base import TASK, EvalPolicy, Observation, active_rows, scatter_rows
from mobilemani_vla.inference import VLAPolicy
from mobilemani_vla.model.processor import camera_key


class GraspPointError:
    """The error a VLA trained with `inputs.grasp_point_noise` sees on its grasp point input: one world-frame
    offset per env, i.e. per episode, since each env runs one episode per batch; N(0, std^2) on each axis."""

    def __init__(self, std: float, num_envs: int, seed: int) -> None:
        self.std = std
        self.offsets = std * np.random.default_rng(seed).standard_normal((num_envs, 3))

    def __call__(self, grasp_point_base: np.ndarray, base_quat: np.ndarray) -> np.ndarray:
        """Base-frame grasp points (n, 3) -> the same points moved by each env's offset, which the base's
        turn (unit quaternions (n, 4)) brings into its frame."""
        moved = grasp_point_base + quat_apply(quat_conj(base_quat), self.offsets)
        return moved.astype(np.float32)


class VLAEvalPolicy(EvalPolicy):
    name = "vla"
    action_frame = "base"

    def __init__(
        self, checkpoint: str | Path, device: str = "cpu", batch_size: int = 16, null_image: bool = False
    ) -> None:
        self.policy = VLAPolicy.load(checkpoint, device)
        if null_image and self.policy.cfg.diffusion.cfg_dropout == 0:
            raise InputError(
                f"policy.null_image=true needs a VLA trained with diffusion.cfg_dropout > 0; {checkpoint} "
                "has no null vector"
            )
        self.null_image = null_image
        self.image_size = recorded_image_size(checkpoint)  # render as the training data was rendered
        self.training = training_scale(checkpoint, self.policy.cfg)
        self.batch_size = batch_size
        self.action_dim = self.policy.cfg.action_dim
        self.chunk_length = self.policy.cfg.diffusion.chunk
        self.inputs = frozenset(
            {camera_key(c) for c in self.policy.cameras} | set(self.policy.vector_inputs) | {TASK}
        )

    def start(self, env: MobileManiEnv, seed: int) -> None:
        # Diffusion noise, reproducible per batch;
        # on the model's device so CUDA sampling needs no host copies.
        self.generator = torch.Generator(self.policy.device).manual_seed(seed)
        self.env = env
        self.grasp_point_error = GraspPointError(self.policy.cfg.inputs.grasp_point_noise, env.num_envs, seed)

    def act(self, obs: Observation) -> np.ndarray:
        if self.grasp_point_error.std > 0:
            point = self.grasp_point_error(obs[schema.GRASP_POINT_BASE], self.env.frames.base_quat)
            obs = {**obs, schema.GRASP_POINT_BASE: point}
        rows = active_rows(obs)
        chunks = []
        for part in np.array_split(rows, max(1, -(-len(rows) // self.batch_size))):
            if part.size:
                images = {c: obs[camera_key(c)][part] for c in self.policy.cameras}
                vectors = {k: obs[k][part] for k in self.policy.vector_inputs}
                chunks.append(
                    self.policy.predict_action_chunks(
                        images, [obs[TASK][i] for i in part], vectors, self.generator, self.null_image
                    )
                )
        return scatter_rows(rows, np.concatenate(chunks), len(obs[TASK]))

"""A LeRobot policy (ACT, pi0, SmolVLA, ... trained with `lerobot-train` on our dataset) as an evaluation
policy.

Loaded from a local `pretrained_model` directory with LeRobot's own API (config, weights, pre/post-processor
pipelines), so normalisation is exactly the one it was trained with. Its input features are our dataset's
feature names (optionally renamed, as with `lerobot-train --rename_map`); images are resized to the feature's
shape. It predicts the dataset's `action` (base frame), one chunk per call (`predict_action_chunk`); the
harness executes the chunks through the adaptive ensemble (default) or takes one fixed element of the newest
(`ensemble.action_index=0`). Policies that stack several observation steps (diffusion with n_obs_steps > 1)
need an observation history and are not supported. Language-conditioned policies (SmolVLA, pi0) get the
instruction as LeRobot's `task` string, which their pre-processor tokenizes; a SmolVLA trained without
downloads reads its VLM config and tokenizer from the local directory it was trained with
(`mobilemani_vla.smolvla_backbone`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F

from mobilemani_data import schema
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.utils.errors import MissingFileError
from mobilemani_rl.utils.io import read_json, weights_sha256
from mobilemani_vla.checkpoint import DATASET
from mobilemani_vla.eval.policies.base import TASK, EvalPolicy, Observation, active_rows, scatter_rows


class LeRobotEvalPolicy(EvalPolicy):
    name = "lerobot"
    action_frame = "base"  # the dataset's `action`

    def __init__(
        self,
        checkpoint: str | Path,
        device: str = "cpu",
        batch_size: int = 16,
        rename: dict[str, str] | None = None,
    ) -> None:
        from lerobot.configs.policies import PreTrainedConfig
        from lerobot.policies.factory import get_policy_class, make_pre_post_processors
        from lerobot.utils.import_utils import register_third_party_plugins

        register_third_party_plugins()  # policy types from plugin packages (MobileManiVLA's among them)
        path = Path(checkpoint)
        if not (path / "config.json").is_file():
            raise MissingFileError(
                f"no LeRobot policy (config.json) in {path}; pass its pretrained_model dir"
            )
        config = PreTrainedConfig.from_pretrained(path)
        config.device = device
        backbone = getattr(config, "vlm_model_name", None)
        # A local backbone directory (SmolVLA without downloads) must still be where training left it;
        # transformers would otherwise take the path for a hub id and fail with an unrelated message.
        if backbone and Path(backbone).is_absolute() and not Path(backbone).is_dir():
            raise MissingFileError(
                f"{config.type}'s VLM backbone directory {backbone} (config and tokenizer) is missing; write "
                "it again with `python -m mobilemani_vla.smolvla_backbone` and the sizes it was trained with"
            )
        if getattr(config, "n_obs_steps", 1) != 1:
            raise ValueError(
                f"{config.type} stacks {config.n_obs_steps} observation steps; only single-step "
                "policies are supported"
            )
        self.policy = get_policy_class(config.type).from_pretrained(path, config=config).eval()
        self.pre, self.post = make_pre_post_processors(config, pretrained_path=str(path))
        self.name = f"lerobot_{config.type}"
        self.batch_size = batch_size
        theirs_to_ours = {theirs: ours for ours, theirs in (rename or {}).items()}
        self.features = {
            theirs_to_ours.get(k, k): (k, tuple(f.shape)) for k, f in config.input_features.items()
        }
        outputs = list(config.output_features)
        if outputs != [schema.ACTION]:
            raise ValueError(
                f"the policy predicts {outputs}; expected [{schema.ACTION!r}] (the dataset's base-frame "
                "action)"
            )
        self.action_dim = int(config.output_features[schema.ACTION].shape[0])
        self.inputs = frozenset(self.features) | {TASK}
        self.windowed = config.observation_delta_indices is not None
        self.training = lerobot_training_scale(path, config.type)
        visual = [shape for _, shape in self.features.values() if len(shape) == 3]
        if visual:  # render as the training dataset was rendered: (C, H, W) of its first image feature
            self.image_size = visual[0][1:]

    def start(self, env: MobileManiEnv, seed: int) -> None:
        # LeRobot's policies draw their noise (diffusion, SmolVLA's flow matching) from torch's global
        # generator. Seeding it per batch makes a block's episodes the same whichever blocks ran before it, in
        # this process or in another evaluation worker.
        torch.manual_seed(seed)

    def _batch(self, obs: Observation, rows: np.ndarray) -> dict:
        batch: dict = {TASK: [obs[TASK][i] for i in rows]}
        for ours, (theirs, shape) in self.features.items():
            value = torch.as_tensor(np.asarray(obs[ours])[rows])
            if value.ndim == 4:  # (B, H, W, 3) uint8 -> (B, 3, H, W) in [0, 1] at the feature's size
                value = value.permute(0, 3, 1, 2).float() / 255.0
                if tuple(value.shape[-2:]) != shape[-2:]:
                    value = F.interpolate(
                        value, size=shape[-2:], mode="bilinear", antialias=True, align_corners=False
                    )
            # Policies trained on observation windows (Diffusion Policy: observation_delta_indices) get a time
            # axis of length 1, as LeRobot's loader gave them in training;
            # the others (ACT) take single frames.
            batch[theirs] = value.float().unsqueeze(1) if self.windowed else value.float()
        return batch

    @torch.no_grad()
    def act(self, obs: Observation) -> np.ndarray:
        rows = active_rows(obs)
        chunks = []
        for part in np.array_split(rows, max(1, -(-len(rows) // self.batch_size))):
            if part.size:
                chunk = self.policy.predict_action_chunk(self.pre(self._batch(obs, part)))
                chunks.append(self.post(chunk).cpu().numpy())
        return scatter_rows(rows, np.concatenate(chunks), len(obs[TASK]))


def lerobot_training_scale(pretrained: Path, policy_type: str) -> dict:
    """How much training a `lerobot-train` checkpoint holds, from the step it records beside
    `pretrained_model` and its training config's batch (per process); only the policy type where the step is
    not there (a pretrained_model copied on its own); the digest of its dataset where its run recorded one
    (mobilemani_vla.lerobot_train); always the digest of its weights."""
    identity = {"model": policy_type, "weights_sha256": weights_sha256(pretrained)}
    record = pretrained.parents[2] / DATASET  # <run>/checkpoints/<step>/pretrained_model
    if record.is_file():
        identity["dataset_sha256"] = read_json(record)["sha256"]
    state = pretrained.parent / "training_state" / "training_step.json"
    if not state.is_file():
        return identity
    recorded = read_json(state)
    per_process = recorded.get("batch_size") or read_json(pretrained / "train_config.json")["batch_size"]
    batch = per_process * (recorded.get("num_processes") or 1)
    step = recorded["step"]
    return {**identity, "steps": step, "batch_size": batch, "samples": step * batch}

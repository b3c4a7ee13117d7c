"""Turns LeRobot frames (or live observations shaped like them) into model batches.

One code path for training and inference, over a batch held feature by feature (`collate`): cameras (uint8,
or float in [0, 1]) resized to the backbone's image size, state inputs normalised and concatenated, prompts
tokenised (left-padded), action chunks normalised with padding handled. Training stacks its dataset frames
into such a batch (`__call__`); the evaluator builds one from its env batch directly, each camera converted
and resized as one (B, 3, H, W) view (frame by frame, it took a large share of an evaluation block at 520 px).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import torch
import torch.nn.functional as F
from transformers import PreTrainedTokenizerBase

from mobilemani_data import schema
from mobilemani_vla.config import VLACfg
from mobilemani_vla.model.normalizer import Normalizer

# Each state input -> (the dataset feature holding it, its part of that feature). Normalisation bounds are per
# feature, so a part is normalised with its feature's bounds.
STATE_SOURCES = {
    "wrist_pose": (schema.STATE, slice(0, schema.WRIST_POSE_DIM)),
    "grasp_point": (schema.GRASP_POINT_BASE, slice(0, 3)),
    "goal_point": (schema.GOAL_POINT_BASE, slice(0, 3)),
}
STATE_DIMS = {name: part.stop - part.start for name, (_, part) in STATE_SOURCES.items()}


def states_width(states: list[str]) -> int:
    """The width of the states `states` concatenated."""
    return sum(STATE_DIMS[s] for s in states)


WRIST_DELTA_DIMS = 6  # action[0:6] are wrist deltas; action[6:] absolute gripper/hand targets


def state_features(states: list[str]) -> list[str]:
    """The dataset features the state inputs `states` are read from, each once."""
    return list(dict.fromkeys(STATE_SOURCES[s][0] for s in states))


def camera_key(camera: str) -> str:
    """'head_rgb' -> the schema's feature name."""
    name, modality = camera.split("_")
    return schema.image_key(name, modality)


def resize_images(images: torch.Tensor, size: int) -> torch.Tensor:
    """(..., 3, H, W) float -> (..., 3, size, size), antialiased bilinear (a no-op at the right size)."""
    if images.shape[-2:] == (size, size):
        return images
    flat = images.reshape(-1, *images.shape[-3:])
    out = F.interpolate(flat, size=(size, size), mode="bilinear", antialias=True, align_corners=False)
    return out.reshape(*images.shape[:-2], size, size)


def as_unit_float(image: torch.Tensor) -> torch.Tensor:
    """uint8 images -> float in [0, 1] (in place on the one float copy); float images pass through."""
    return image.float().div_(255.0) if image.dtype == torch.uint8 else image.float()


@dataclass
class VLAProcessor:
    tokenizer: PreTrainedTokenizerBase
    normalizer: Normalizer
    cameras: list[str]
    states: list[str]
    image_size: int
    prompt: str
    targets: list[str] = field(default_factory=list)  # states the cognition feature learns to regress
    grasp_point_noise: float = 0.0  # std (m) of the error put on dataset frames' grasp point input

    @classmethod
    def for_config(
        cls, cfg: VLACfg, tokenizer: PreTrainedTokenizerBase, normalizer: Normalizer, image_size: int
    ) -> VLAProcessor:
        """The processor a model trained with `cfg` reads its inputs through."""
        return cls(
            tokenizer,
            normalizer,
            cfg.inputs.cameras,
            cfg.inputs.states,
            image_size,
            cfg.model.prompt,
            cfg.train.cognition_targets,
            cfg.inputs.grasp_point_noise,
        )

    def __post_init__(self) -> None:
        needed = [schema.ACTION, *state_features(self.states + self.targets)]
        if missing := [k for k in needed if k not in self.normalizer.bounds]:
            raise KeyError(
                f"the normalisation bounds have no {missing} (they hold {sorted(self.normalizer.bounds)}): "
                "the checkpoint was trained on an older dataset layout; retrain it on a current export"
            )

    @property
    def state_dim(self) -> int:
        return states_width(self.states)

    def images(self, batch: dict) -> torch.Tensor:
        """Selected cameras, each (B, 3, H, W) uint8 or float in [0, 1] -> (B, K, 3, S, S) float."""
        resized = [resize_images(as_unit_float(batch[camera_key(c)]), self.image_size) for c in self.cameras]
        return torch.stack(resized, dim=1).contiguous()  # an (H, W, 3) camera view resizes channels-last

    def state(self, batch: dict, states: list[str] | None = None) -> torch.Tensor:
        """The normalised `states` (default: the state inputs), concatenated."""
        parts = [
            self.normalizer.normalize(key, torch.as_tensor(batch[key]))[..., part]
            for key, part in (STATE_SOURCES[s] for s in (self.states if states is None else states))
        ]
        return torch.cat(parts, dim=-1)

    def actions(self, batch: dict) -> torch.Tensor:
        """Normalised chunks (B, N, A). Rows past the episode end (LeRobot repeats the last action there) get
        the normalised zero wrist delta, i.e. "hold still", and keep the last gripper/hand target. As in
        CogACT's loader, the model then learns to stop at the end of a task, and the loss keeps all B x N x A
        terms."""
        chunk = self.normalizer.normalize(schema.ACTION, torch.as_tensor(batch[schema.ACTION]))
        pad = torch.as_tensor(batch[f"{schema.ACTION}_is_pad"], dtype=torch.bool)
        still = self.normalizer.normalize(schema.ACTION, torch.zeros(chunk.shape[-1]))[:WRIST_DELTA_DIMS]
        chunk[..., :WRIST_DELTA_DIMS][pad] = still
        return chunk

    def tokenize(self, instructions: list[str]) -> dict[str, torch.Tensor]:
        prompts = [self.prompt.format(instruction=text) + "\n" for text in instructions]
        enc = self.tokenizer(prompts, padding=True, return_tensors="pt")
        return {"input_ids": enc["input_ids"], "attention_mask": enc["attention_mask"]}

    def collate(self, batch: dict) -> dict[str, torch.Tensor]:
        """Model inputs from a batch held feature by feature: cameras (B, 3, H, W), state features (B, d),
        `task` (B instructions) and, in training, `action` (B, N, A) with its `action_is_pad` (B, N)."""
        out = {"pixel_values": self.images(batch), **self.tokenize(list(batch["task"]))}
        if self.states:
            out["state"] = self.state(batch)
        if schema.ACTION in batch:
            out["actions"] = self.actions(batch)
            if self.targets:
                out["cognition_target"] = self.state(batch, self.targets)
        return out

    def __call__(self, frames: list[dict]) -> dict[str, torch.Tensor]:
        """Collate dataset frames (the training loader's collate_fn)."""
        keys = [camera_key(c) for c in self.cameras] + state_features(self.states)
        if schema.ACTION in frames[0]:
            keys += [schema.ACTION, f"{schema.ACTION}_is_pad"]
            keys += [k for k in state_features(self.targets) if k not in keys]
        batch = {k: torch.stack([torch.as_tensor(f[k]) for f in frames]) for k in keys}
        out = self.collate({**batch, "task": [f["task"] for f in frames]})
        if self.grasp_point_noise > 0:  # the input only: a grasp-point target stays exact
            out["state"] = self.state(self.with_grasp_point_error(batch))
        return out

    def with_grasp_point_error(self, batch: dict) -> dict:
        """The batch with each frame's grasp point off by N(0, grasp_point_noise^2) on each axis. An
        isotropic error looks the same in every frame, so a draw in the base frame stands for the
        evaluator's world-frame one (`VLAEvalPolicy`)."""
        point = torch.as_tensor(batch[schema.GRASP_POINT_BASE])
        return {**batch, schema.GRASP_POINT_BASE: point + self.grasp_point_noise * torch.randn_like(point)}

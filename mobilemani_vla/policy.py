"""Inference API for the closed-loop evaluator: one observation -> one un-normalised base-frame action chunk."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from mobilemani_data import schema
from mobilemani_vla.checkpoint import load_checkpoint
from mobilemani_vla.config import STATES, VLACfg
from mobilemani_vla.model import MobileManiVLA
from mobilemani_vla.processor import STATE_DIMS, STATE_KEYS, VLAProcessor, camera_key

# The `state` vector handed to the policy: every state input in this order (12 values); a model reads the ones
# its config enables.
STATE_SLICES = {name: slice(start, start + STATE_DIMS[name])
                for name, start in zip(STATES, np.cumsum([0] + [STATE_DIMS[s] for s in STATES]), strict=False)}
FULL_STATE_DIM = sum(STATE_DIMS.values())


class VLAPolicy:
    def __init__(self, cfg: VLACfg, model: MobileManiVLA, processor: VLAProcessor,
                 device: str | torch.device = "cpu") -> None:
        self.cfg = cfg
        self.model = model.to(device).eval()
        self.processor = processor
        self.device = torch.device(device)

    @classmethod
    def load(cls, checkpoint: str | Path, device: str | torch.device = "cpu") -> VLAPolicy:
        cfg, model, normalizer, tokenizer = load_checkpoint(checkpoint, device)
        processor = VLAProcessor(tokenizer, normalizer, cfg.inputs.cameras, cfg.inputs.states,
                                 model.backbone.image_size, cfg.model.prompt)
        return cls(cfg, model, processor, device)

    @property
    def cameras(self) -> list[str]:
        return self.cfg.inputs.cameras

    def predict_action_chunk(self, images: dict[str, np.ndarray], instruction: str, state: np.ndarray,
                             generator: torch.Generator | None = None) -> np.ndarray:
        """images: camera name ("head_rgb", "wrist_depth", ...) -> (H, W, 3) uint8, at least this policy's
        cameras; state: (12,) wrist pose (6), first-frame grasp point (3), goal point (3), all in the base frame.
        Returns (chunk, action_dim) base-frame actions in the dataset's units."""
        batched = {c: np.asarray(v)[None] for c, v in images.items()}
        return self.predict_action_chunks(batched, [instruction], np.asarray(state)[None], generator)[0]

    def predict_action_chunks(self, images: dict[str, np.ndarray], instructions: list[str], states: np.ndarray,
                              generator: torch.Generator | None = None) -> np.ndarray:
        """Batched `predict_action_chunk`: images (B, H, W, 3), B instructions, states (B, 12) -> (B, chunk, A)."""
        missing = [c for c in self.cameras if c not in images]
        if missing:
            raise KeyError(f"missing camera images {missing}; this policy reads {self.cameras}")
        states = np.asarray(states, np.float32)
        if states.shape != (len(instructions), FULL_STATE_DIM):
            raise ValueError(f"states must have shape (batch, {FULL_STATE_DIM}) (wrist pose, grasp point, goal "
                             f"point), got {states.shape}")
        frames = []
        for i, instruction in enumerate(instructions):
            frame = {camera_key(c): torch.from_numpy(np.ascontiguousarray(images[c][i])).permute(2, 0, 1).float()
                     / 255.0 for c in self.cameras}
            frame.update({STATE_KEYS[s]: torch.from_numpy(states[i, STATE_SLICES[s]]) for s in self.cfg.inputs.states})
            frame["task"] = instruction
            frames.append(frame)
        batch = {k: v.to(self.device) for k, v in self.processor(frames).items()}
        chunks = self.model.predict(batch, generator)
        return self.processor.normalizer.unnormalize(schema.ACTION_BASE, chunks).cpu().numpy()

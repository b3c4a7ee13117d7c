"""Inference API for the closed-loop evaluator:
one observation -> one un-normalised base-frame action chunk."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from mobilemani_data import schema
from mobilemani_vla.checkpoint import load_checkpoint
from mobilemani_vla.config import VLACfg
from mobilemani_vla.model.network import MobileManiVLA
from mobilemani_vla.model.processor import VLAProcessor, camera_key, state_features


class VLAPolicy:
    def __init__(
        self, cfg: VLACfg, model: MobileManiVLA, processor: VLAProcessor, device: str | torch.device = "cpu"
    ) -> None:
        self.cfg = cfg
        self.model = model.to(device).eval()
        self.processor = processor
        # The device the weights landed on, with its index ("cuda" -> cuda:0): the noise generator and the
        # batches are made there, and torch.device("cuda") != torch.device("cuda:0").
        self.device = next(self.model.parameters()).device

    @classmethod
    def load(cls, checkpoint: str | Path, device: str | torch.device = "cpu") -> VLAPolicy:
        cfg, model, normalizer, tokenizer = load_checkpoint(checkpoint, device)
        processor = VLAProcessor.for_config(cfg, tokenizer, normalizer, model.backbone.image_size)
        return cls(cfg, model, processor, device)

    @property
    def cameras(self) -> list[str]:
        return self.cfg.inputs.cameras

    @property
    def vector_inputs(self) -> list[str]:
        """The dataset's vector features this policy's state inputs are read from."""
        return state_features(self.cfg.inputs.states)

    def predict_action_chunk(
        self,
        images: dict[str, np.ndarray],
        instruction: str,
        vectors: dict[str, np.ndarray],
        generator: torch.Generator | None = None,
    ) -> np.ndarray:
        """images: camera name ("head_rgb", "wrist_depth", ...) -> (H, W, 3) uint8, at least this policy's
        cameras; vectors: dataset feature name -> (d,) values, at least `vector_inputs` (the frame builder,
        mobilemani_data.frame, makes both). Returns
        (chunk, action_dim) base-frame actions in the dataset's units."""
        batched = {c: np.asarray(v)[None] for c, v in images.items()}
        return self.predict_action_chunks(
            batched, [instruction], {k: np.asarray(v)[None] for k, v in vectors.items()}, generator
        )[0]

    def predict_action_chunks(
        self,
        images: dict[str, np.ndarray],
        instructions: list[str],
        vectors: dict[str, np.ndarray],
        generator: torch.Generator | None = None,
        null_image: bool = False,
    ) -> np.ndarray:
        """Batched `predict_action_chunk`: images (B, H, W, 3), B instructions, vectors (B, d)
        -> (B, chunk, A); `null_image`: the model's null vector in place of its image feature."""
        missing = [c for c in self.cameras if c not in images] + [
            k for k in self.vector_inputs if k not in vectors
        ]
        if missing:
            raise KeyError(
                f"missing inputs {missing}; this policy reads cameras {self.cameras} and vectors "
                f"{self.vector_inputs}"
            )
        # One (B, 3, H, W) view per camera: converted and resized as a whole, not frame by frame.
        inputs = {
            camera_key(c): torch.from_numpy(np.ascontiguousarray(images[c])).permute(0, 3, 1, 2)
            for c in self.cameras
        }
        inputs.update({k: torch.from_numpy(np.asarray(vectors[k], np.float32)) for k in self.vector_inputs})
        inputs["task"] = instructions
        batch = {k: v.to(self.device) for k, v in self.processor.collate(inputs).items()}
        chunks = self.model.predict(batch, generator, null_image)
        return self.processor.normalizer.unnormalize(schema.ACTION, chunks).cpu().numpy()

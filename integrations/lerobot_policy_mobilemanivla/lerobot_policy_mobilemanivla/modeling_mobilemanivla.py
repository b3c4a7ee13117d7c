"""MobileManiVLA as a LeRobot `PreTrainedPolicy`, wrapping the project's model code: the network
(mobilemani_vla.model.network.build_model), its batch processor (tokenizer, image resizing, normalisation,
padded chunk rows: mobilemani_vla.model.processor) and the adaptive ensemble (mobilemani_vla.model.ensemble).

Training is LeRobot's loop (`lerobot-train`): no EMA of the weights and no image augmentation, which our own
trainer (python -m mobilemani_vla.train) adds. The normalisation bounds are the dataset's global per-dimension
min/max from its stats (Normalizer.fit's bounds when the dataset is the training split), kept as buffers so
that they travel in model.safetensors; the word-level tokenizer is rebuilt from the instructions the config
records.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import torch
from lerobot.policies.pretrained import PreTrainedPolicy
from lerobot.utils.constants import ACTION, OBS_STATE
from torch import Tensor

from lerobot_policy_mobilemanivla.configuration_mobilemanivla import MobileManiVLAConfig
from mobilemani_rl.utils.errors import InputError
from mobilemani_vla.model.ensemble import ChunkExecutor
from mobilemani_vla.model.network import build_model
from mobilemani_vla.model.normalizer import Normalizer
from mobilemani_vla.model.processor import VLAProcessor
from mobilemani_vla.model.tokenizer import load_tokenizer


def stats_bounds(stats: Mapping | None, key: str, width: int) -> Tensor:
    """(2, width): the dataset's min and max of `key`; without stats (a checkpoint about to load its own)
    [-1, 1]."""
    if stats is None:
        return torch.stack([-torch.ones(width), torch.ones(width)])
    if key not in stats:
        raise InputError(f"the dataset's stats have no {key!r}; they hold {sorted(stats)}")
    return torch.stack(
        [torch.as_tensor(np.asarray(stats[key][s]), dtype=torch.float32) for s in ("min", "max")]
    )


class MobileManiVLAPolicy(PreTrainedPolicy):
    config_class = MobileManiVLAConfig
    name = "mobilemanivla"

    def __init__(
        self,
        config: MobileManiVLAConfig,
        dataset_stats: Mapping | None = None,
        dataset_meta: object | None = None,
        **kwargs: object,
    ) -> None:
        super().__init__(config)
        if dataset_meta is not None and not config.tasks:  # the same instructions as our trainer tokenizes
            config.tasks = sorted(dataset_meta.tasks.index)
        config.validate_features()
        self.vla = config.vla_cfg()
        self.tokenizer = load_tokenizer(self.vla.model.tokenizer_path, config.tasks)
        self.model = build_model(self.vla, self.tokenizer)
        state = config.input_features.get(OBS_STATE)
        self.register_buffer("action_bounds", stats_bounds(dataset_stats, ACTION, self.vla.action_dim))
        if state is not None:
            self.register_buffer("state_bounds", stats_bounds(dataset_stats, OBS_STATE, state.shape[0]))
        self.executor: ChunkExecutor | None = None

    def processor(self) -> VLAProcessor:
        bounds = {ACTION: self.action_bounds}
        if hasattr(self, "state_bounds"):
            bounds[OBS_STATE] = self.state_bounds
        normalizer = Normalizer({k: (b[0].cpu().numpy(), b[1].cpu().numpy()) for k, b in bounds.items()})
        return VLAProcessor.for_config(self.vla, self.tokenizer, normalizer, self.model.backbone.image_size)

    def _inputs(self, processor: VLAProcessor, batch: dict) -> dict[str, Tensor]:
        device = self.action_bounds.device
        return {k: v.to(device) for k, v in processor.collate(batch).items()}

    def get_optim_params(self) -> list[Tensor]:
        return [p for p in self.parameters() if p.requires_grad]

    def reset(self) -> None:
        self.executor = None  # a new rollout: the ensemble starts without chunks

    def forward(self, batch: dict[str, Tensor]) -> tuple[Tensor, dict]:
        """The diffusion loss of a LeRobot batch (cameras, state, instruction, padded action chunk)."""
        loss = self.model(self._inputs(self.processor(), batch))
        return loss, {"loss": loss.item()}

    @torch.no_grad()
    def predict_action_chunk(self, batch: dict[str, Tensor], **kwargs: object) -> Tensor:
        """(B, chunk, action_dim) base-frame actions in the dataset's units."""
        processor = self.processor()
        inputs = {k: v for k, v in batch.items() if k != ACTION}
        chunks = self.model.predict(self._inputs(processor, inputs))
        return processor.normalizer.unnormalize(ACTION, chunks)

    @torch.no_grad()
    def select_action(self, batch: dict[str, Tensor], **kwargs: object) -> Tensor:
        """A chunk every step, executed through the adaptive ensemble (or one fixed element of it,
        `--policy.ensemble.action_index`), as our harness executes it."""
        chunks = self.predict_action_chunk(batch)
        if self.executor is None or len(self.executor.ensemblers) != len(chunks):
            self.executor = ChunkExecutor(self.config.ensemble, len(chunks))
        actions = self.executor(chunks.cpu().numpy())
        return torch.as_tensor(actions, dtype=torch.float32, device=chunks.device)

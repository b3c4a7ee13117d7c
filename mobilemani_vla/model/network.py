"""MobileManiVLA: cognition feature from PaliGemma + state feature -> DiT diffusion over base-frame
actions."""

from __future__ import annotations

import torch
import torch.nn.functional as F
from torch import nn
from transformers import PaliGemmaConfig, PreTrainedTokenizerBase
from transformers.models.paligemma.modeling_paligemma import PaliGemmaModel

from mobilemani_vla.config import VLACfg
from mobilemani_vla.model.backbone import CognitionBackbone, load_paligemma, paligemma_config
from mobilemani_vla.model.diffusion import ActionDiffusion
from mobilemani_vla.model.dit import DiT
from mobilemani_vla.model.processor import states_width


class StateEncoder(nn.Module):
    """Small MLP over the base-frame wrist pose (+ first-frame grasp / goal points) -> one DiT-width
    vector."""

    def __init__(self, in_dim: int, width: int) -> None:
        super().__init__()
        self.mlp = nn.Sequential(nn.Linear(in_dim, width), nn.SiLU(), nn.Linear(width, width))

    def forward(self, state: torch.Tensor) -> torch.Tensor:
        return self.mlp(state)


class MobileManiVLA(nn.Module):
    def __init__(self, cfg: VLACfg, backbone: CognitionBackbone) -> None:
        super().__init__()
        self.action_dim = cfg.action_dim
        self.backbone = backbone
        dit = DiT(
            cfg.model.dit,
            cfg.action_dim,
            cfg.diffusion.chunk,
            backbone.width,
            cfg.diffusion.cfg_dropout > 0,
            cfg.model.dit_gelu,
        )
        state_dim = states_width(cfg.inputs.states)
        self.state_encoder = StateEncoder(state_dim, dit.width) if state_dim else None
        self.head = ActionDiffusion(dit, cfg.diffusion)
        self.state_dropout = cfg.inputs.state_dropout
        target_dim = states_width(cfg.train.cognition_targets)
        self.cognition_probe = nn.Linear(backbone.width, target_dim) if target_dim else None
        self.cognition_target_weight = cfg.train.cognition_target_weight

    def condition(self, batch: dict[str, torch.Tensor]) -> tuple[torch.Tensor, torch.Tensor | None]:
        head_dtype = self.head.dit.pos_embed.dtype  # a bfloat16 backbone feeds a float32 head
        cognition = self.backbone(batch["pixel_values"], batch["input_ids"], batch["attention_mask"]).to(
            head_dtype
        )
        state = None if self.state_encoder is None else self.state_encoder(batch["state"].to(head_dtype))
        return cognition, state

    def forward(self, batch: dict[str, torch.Tensor]) -> torch.Tensor:
        """Training loss: the diffusion loss, plus the weighted cognition-target error where there are
        targets."""
        cognition, state = self.condition(batch)
        if state is not None and self.state_dropout > 0 and self.training:
            kept = torch.rand(state.shape[0], 1, device=state.device) >= self.state_dropout
            state = state * kept  # a withheld state is the zero feature, as the no-state diagnostic feeds
        loss = self.head.loss(batch["actions"], cognition, state)
        if self.cognition_probe is not None:
            loss = loss + self.cognition_target_weight * self.cognition_target_error(cognition, batch)
        return loss

    def cognition_target_error(self, cognition: torch.Tensor, batch: dict[str, torch.Tensor]) -> torch.Tensor:
        """MSE of the linear read-out of the cognition feature against its targets (normalised units)."""
        return F.mse_loss(self.cognition_probe(cognition).float(), batch["cognition_target"].float())

    @torch.no_grad()
    def predict(
        self,
        batch: dict[str, torch.Tensor],
        generator: torch.Generator | None = None,
        null_image: bool = False,
    ) -> torch.Tensor:
        """Normalised action chunks (B, N, A); `null_image`: sampled from the guidance's null vector alone
        (the "unconditional" input, which stands for the whole cognition feature), without guidance."""
        cognition, state = self.condition(batch)
        return self.head.sample(cognition, state, self.action_dim, generator, unconditional=null_image)


def build_model(
    cfg: VLACfg, tokenizer: PreTrainedTokenizerBase, backbone_config: PaliGemmaConfig | None = None
) -> MobileManiVLA:
    """From a saved backbone config (checkpoint reload), a local pretrained directory, or the model config.
    Call under `torch.device("meta")` to get the architecture without allocating weights."""
    if backbone_config is not None:
        vlm = PaliGemmaModel(backbone_config)
    elif cfg.model.pretrained_path is not None:
        vlm = load_paligemma(
            cfg.model.pretrained_path, cfg.model.attn_implementation, getattr(torch, cfg.model.dtype)
        )
    else:
        vlm = PaliGemmaModel(paligemma_config(cfg.model))
    vocab = vlm.config.text_config.vocab_size
    if len(tokenizer) > vocab:
        raise ValueError(f"tokenizer has {len(tokenizer)} tokens but the backbone's vocabulary has {vocab}")
    return MobileManiVLA(cfg, CognitionBackbone(vlm, tokenizer.eos_token_id))

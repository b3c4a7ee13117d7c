"""PaliGemma (SigLIP + Gemma-2) encoder that reads a cognition token.

Sequence per sample: [camera_1 patches … camera_k patches][<bos> prompt tokens][cognition].
The images and prompt form PaliGemma's bidirectional prefix (token type 0); the cognition token is a single
causal suffix token (type 1), so it attends to everything while the pretrained prefix attention is unchanged.
Prompts are left-padded, which keeps the cognition token at position -1 of every row.
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

import torch
from torch import nn
from transformers import Gemma2Config, PaliGemmaConfig, PaliGemmaForConditionalGeneration, SiglipVisionConfig
from transformers.models.paligemma.modeling_paligemma import PaliGemmaModel, create_causal_mask_mapping

from mobilemani_rl.utils.errors import MissingFileError
from mobilemani_vla.config import ModelCfg


def paligemma_config(cfg: ModelCfg) -> PaliGemmaConfig:
    """The backbone architecture described by a model config (no weights)."""
    # VisionCfg and TextCfg name their fields as these configs' arguments.
    t = cfg.text
    vision = SiglipVisionConfig(**asdict(cfg.vision), vision_use_head=False)
    text = Gemma2Config(**asdict(t))
    # The image token id sits just past the text vocabulary, as in PaliGemma-2 (we never embed it).
    config = PaliGemmaConfig(
        vision_config=vision,
        text_config=text,
        image_token_index=t.vocab_size,
        vocab_size=t.vocab_size,
        projection_dim=t.hidden_size,
        hidden_size=t.hidden_size,
    )
    if cfg.attn_implementation is not None:
        config._attn_implementation = cfg.attn_implementation
    return config


def load_paligemma(
    path: str | Path, attn_implementation: str | None = None, dtype: torch.dtype = torch.float32
) -> PaliGemmaModel:
    """Pretrained weights from a local directory only (no hub access), in `dtype`; the LM head is dropped."""
    if not (Path(path) / "config.json").is_file():
        raise MissingFileError(
            f"no PaliGemma checkpoint at {path} (model.pretrained_path needs config.json + "
            "safetensors; real PaliGemma-2 weights must be placed on disk by hand)"
        )
    kwargs = {"attn_implementation": attn_implementation} if attn_implementation else {}
    full = PaliGemmaForConditionalGeneration.from_pretrained(
        str(path), local_files_only=True, dtype=dtype, **kwargs
    )
    return full.model


class CognitionBackbone(nn.Module):
    def __init__(self, vlm: PaliGemmaModel, init_token_id: int) -> None:
        super().__init__()
        self.vlm = vlm
        # A learned embedding row, started from the (scaled) embedding of `init_token_id` (EOS, as in CogACT).
        with torch.no_grad():
            row = vlm.get_input_embeddings()(torch.tensor([init_token_id], device=vlm.device))[0]
        self.cognition = nn.Parameter(row.detach().clone())

    @property
    def width(self) -> int:
        return self.vlm.config.text_config.hidden_size

    @property
    def image_size(self) -> int:
        return self.vlm.config.vision_config.image_size

    @property
    def tokens_per_image(self) -> int:
        return self.vlm.config.text_config.num_image_tokens

    def image_tokens(self, pixel_values: torch.Tensor) -> torch.Tensor:
        """pixel_values (B, K, 3, S, S) in [0, 1] -> (B, K * tokens_per_image, width)."""
        b = pixel_values.shape[0]
        pixels = pixel_values.flatten(0, 1) * 2.0 - 1.0  # SigLIP's mean/std of 0.5
        features = self.vlm.get_image_features(pixels.to(self.cognition.dtype)).pooler_output
        return features.reshape(b, -1, features.shape[-1])

    def forward(
        self, pixel_values: torch.Tensor, input_ids: torch.Tensor, attention_mask: torch.Tensor
    ) -> torch.Tensor:
        """-> the cognition token's last-layer (post-norm) hidden state, (B, width)."""
        images = self.image_tokens(pixel_values)
        text = self.vlm.get_input_embeddings()(input_ids)
        b, n_img, n_txt = images.shape[0], images.shape[1], text.shape[1]
        cognition = self.cognition.to(text.dtype).expand(b, 1, -1)
        embeds = torch.cat([images.to(text.dtype), text, cognition], dim=1)
        ones = attention_mask.new_ones(b, 1)
        mask = torch.cat([ones.expand(b, n_img), attention_mask, ones], dim=1)
        positions = (mask.cumsum(-1) * mask).clamp(min=1)  # PaliGemma counts from 1; pads are skipped
        token_type = torch.cat([mask.new_zeros(b, n_img + n_txt), ones], dim=1)
        out = self.vlm(
            inputs_embeds=embeds,
            attention_mask=self.attention_masks(embeds, mask, positions, token_type),
            position_ids=positions,
            token_type_ids=token_type,
            use_cache=False,
        )
        return out.last_hidden_state[:, -1]

    def attention_masks(
        self, embeds: torch.Tensor, mask: torch.Tensor, positions: torch.Tensor, token_type: torch.Tensor
    ) -> dict:
        """PaliGemma's per-layer-type attention masks. Under SDPA (the default) a few tensor ops,
        prefix_lm_masks; transformers' own builder runs nested vmaps, a third of a small model's CPU forward
        pass. Other attention implementations take its builder's masks (additive ones, for eager)."""
        text_config = self.vlm.config.text_config
        if text_config._attn_implementation == "sdpa" and text_config.sliding_window >= mask.shape[1]:
            return prefix_lm_masks(mask, token_type, text_config.layer_types)
        return create_causal_mask_mapping(
            self.vlm.config, embeds, mask, None, positions, token_type, None, is_training=self.training
        )


def prefix_lm_masks(mask: torch.Tensor, token_type: torch.Tensor, layer_types: list[str]) -> dict:
    """Boolean SDPA masks (B, 1, L, L) for every layer type, as PaliGemma builds them for a sequence shorter
    than the sliding window: a query attends to every unpadded key before it, and prefix tokens (type 0) to
    the whole unpadded prefix."""
    length = mask.shape[1]
    causal = torch.ones(length, length, dtype=torch.bool, device=mask.device).tril()
    prefix = token_type == 0
    allowed = (causal | (prefix[:, :, None] & prefix[:, None, :])) & mask.bool()[:, None, :]
    return dict.fromkeys(layer_types, allowed[:, None])

"""CogACT's diffusion-transformer action head.

One condition token c = timestep embedding + projected cognition feature (+ state feature) is prepended to the
embedded noisy action chunk; a learned positional embedding is added; pre-LN transformer blocks (no adaLN)
run over the chunk + 1 tokens; a zero-initialised linear reads the noise off every action token.
"""

from __future__ import annotations

import math

import torch
import torch.nn.functional as F
from torch import nn

# (depth, width, heads): CogACT's S/B/L, plus "Ti", the same block stack narrowed for CPU tests.
DIT_PRESETS: dict[str, tuple[int, int, int]] = {
    "Ti": (4, 128, 4),
    "S": (6, 384, 4),
    "B": (12, 768, 12),
    "L": (24, 1024, 16),
}
GELU_APPROXIMATIONS = ("tanh", "none")  # torch.nn.GELU's; CogACT's DiT uses tanh


class TimestepEmbedder(nn.Module):
    """Sinusoidal features of the diffusion step (cos half first) -> MLP."""

    def __init__(self, width: int, frequency_dim: int = 256) -> None:
        super().__init__()
        self.frequency_dim = frequency_dim
        self.mlp = nn.Sequential(nn.Linear(frequency_dim, width), nn.SiLU(), nn.Linear(width, width))

    def forward(self, t: torch.Tensor) -> torch.Tensor:
        half = self.frequency_dim // 2
        freqs = torch.exp(
            -math.log(10000.0) * torch.arange(half, device=t.device, dtype=torch.float32) / half
        )
        args = t.float()[:, None] * freqs[None]
        return self.mlp(torch.cat([torch.cos(args), torch.sin(args)], dim=-1).to(self.mlp[0].weight.dtype))


class CognitionEmbedder(nn.Module):
    """Projects the cognition feature; with guidance, a learned null vector of the same width replaces it."""

    def __init__(self, cond_dim: int, width: int, guidance: bool) -> None:
        super().__init__()
        self.proj = nn.Linear(cond_dim, width)
        # Sized to the real condition width (CogACT hard-codes 4096 here, which breaks other backbones).
        self.null = nn.Parameter(torch.randn(cond_dim)) if guidance else None

    def forward(self, cognition: torch.Tensor, drop: torch.Tensor | None = None) -> torch.Tensor:
        if drop is not None:
            if self.null is None:
                raise ValueError(
                    "condition dropout needs a head built with guidance (diffusion.cfg_dropout > 0)"
                )
            cognition = torch.where(drop[:, None], self.null.to(cognition.dtype), cognition)
        return self.proj(cognition)


class Attention(nn.Module):
    def __init__(self, width: int, heads: int) -> None:
        super().__init__()
        self.heads = heads
        self.qkv = nn.Linear(width, 3 * width)
        self.proj = nn.Linear(width, width)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        b, n, w = x.shape
        q, k, v = self.qkv(x).view(b, n, 3, self.heads, w // self.heads).permute(2, 0, 3, 1, 4)
        out = F.scaled_dot_product_attention(q, k, v)  # bidirectional over condition + chunk
        return self.proj(out.transpose(1, 2).reshape(b, n, w))


class Block(nn.Module):
    """Pre-LN transformer block; LayerNorms carry no affine parameters, as in CogACT."""

    def __init__(self, width: int, heads: int, gelu: str = "tanh", mlp_ratio: float = 4.0) -> None:
        super().__init__()
        hidden = int(width * mlp_ratio)
        self.norm1 = nn.LayerNorm(width, elementwise_affine=False, eps=1e-6)
        self.attn = Attention(width, heads)
        self.norm2 = nn.LayerNorm(width, elementwise_affine=False, eps=1e-6)
        self.mlp = nn.Sequential(
            nn.Linear(width, hidden), nn.GELU(approximate=gelu), nn.Linear(hidden, width)
        )

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        x = x + self.attn(self.norm1(x))
        return x + self.mlp(self.norm2(x))


class DiT(nn.Module):
    def __init__(
        self, size: str, action_dim: int, chunk: int, cond_dim: int, guidance: bool, gelu: str = "tanh"
    ) -> None:
        super().__init__()
        depth, width, heads = DIT_PRESETS[size]
        self.width = width
        self.action_embed = nn.Linear(action_dim, width)
        self.t_embed = TimestepEmbedder(width)
        self.cond_embed = CognitionEmbedder(cond_dim, width, guidance)
        self.pos_embed = nn.Parameter(torch.randn(chunk + 1, width) * width**-0.5)
        self.blocks = nn.ModuleList(Block(width, heads, gelu) for _ in range(depth))
        self.final_norm = nn.LayerNorm(width, elementwise_affine=False, eps=1e-6)
        self.out = nn.Linear(width, action_dim)
        self._init_weights()

    def _init_weights(self) -> None:
        for module in self.modules():
            if isinstance(module, nn.Linear):
                nn.init.xavier_uniform_(module.weight)
                nn.init.zeros_(module.bias)
        for linear in (self.action_embed, self.cond_embed.proj, self.t_embed.mlp[0], self.t_embed.mlp[2]):
            nn.init.normal_(linear.weight, std=0.02)
        nn.init.zeros_(self.out.weight)  # the head starts by predicting zero noise
        nn.init.zeros_(self.out.bias)

    def forward(
        self,
        noisy: torch.Tensor,
        t: torch.Tensor,
        cognition: torch.Tensor,
        extra: torch.Tensor | None = None,
        drop: torch.Tensor | None = None,
    ) -> torch.Tensor:
        """noisy (B, N, A), t (B,), cognition (B, cond_dim), extra (B, width) e.g. a state feature
        -> eps (B, N, A)."""
        cond = self.t_embed(t) + self.cond_embed(cognition, drop)
        if extra is not None:
            cond = cond + extra
        x = torch.cat([cond[:, None], self.action_embed(noisy)], dim=1) + self.pos_embed
        for block in self.blocks:
            x = block(x)
        return self.out(self.final_norm(x))[:, 1:]

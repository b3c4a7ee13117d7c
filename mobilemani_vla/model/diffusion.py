"""Epsilon-prediction diffusion over action chunks: CogACT's training loss and DDIM sampling via diffusers."""

from __future__ import annotations

import torch
import torch.nn.functional as F
from diffusers import DDIMScheduler
from torch import nn

from mobilemani_vla.config import DiffusionCfg
from mobilemani_vla.model.dit import DiT


def make_scheduler(cfg: DiffusionCfg) -> DDIMScheduler:
    # "leading" spacing gives t = 90, 80, ..., 0 for 10 steps, CogACT's "ddim10"; CogACT never clips samples.
    return DDIMScheduler(
        num_train_timesteps=cfg.train_timesteps,
        beta_schedule=cfg.beta_schedule,
        prediction_type="epsilon",
        clip_sample=False,
        set_alpha_to_one=True,
        steps_offset=0,
        timestep_spacing="leading",
    )


class ActionDiffusion(nn.Module):
    def __init__(self, dit: DiT, cfg: DiffusionCfg) -> None:
        super().__init__()
        self.dit = dit
        self.cfg = cfg
        self.scheduler = make_scheduler(cfg)  # one instance per sampler: set_timesteps mutates it

    @property
    def guided(self) -> bool:
        return self.cfg.cfg_dropout > 0

    def loss(
        self, actions: torch.Tensor, cognition: torch.Tensor, extra: torch.Tensor | None
    ) -> torch.Tensor:
        """MSE between predicted and true noise; the batch is tiled r times so one backbone pass yields r
        denoising samples, each with its own t and noise."""
        r = self.cfg.repeated_steps
        x0 = actions.repeat(r, 1, 1)
        cognition = cognition.repeat(r, 1)
        extra = None if extra is None else extra.repeat(r, 1)
        t = torch.randint(0, self.cfg.train_timesteps, (x0.shape[0],), device=x0.device)
        noise = torch.randn_like(x0)
        noisy = self.scheduler.add_noise(x0, noise, t)
        drop = None
        if self.guided and self.training:
            drop = torch.rand(x0.shape[0], device=x0.device) < self.cfg.cfg_dropout
        pred = self.dit(noisy, t, cognition, extra, drop)
        return F.mse_loss(pred.float(), noise.float())

    @torch.no_grad()
    def sample(
        self,
        cognition: torch.Tensor,
        extra: torch.Tensor | None,
        action_dim: int,
        generator: torch.Generator | None = None,
        cfg_scale: float | None = None,
        unconditional: bool = False,
    ) -> torch.Tensor:
        """DDIM (eta 0) from pure noise -> normalised chunk (B, N, A); guidance eps_u + s (eps_c - eps_u) with
        s = `cfg_scale` (default: the config's); `unconditional`: the null vector's prediction alone. The
        noise is drawn on the generator's device (a CPU generator stays reproducible whatever device the model
        runs on) and moved to the model's."""
        b = cognition.shape[0]
        scale = self.cfg.cfg_scale if cfg_scale is None else cfg_scale
        noise_device = generator.device if generator is not None else cognition.device
        x = torch.randn(
            b, self.cfg.chunk, action_dim, generator=generator, device=noise_device, dtype=cognition.dtype
        ).to(cognition.device)
        guide = self.guided and scale != 1.0 and not unconditional
        drop = torch.ones(b, dtype=torch.bool, device=x.device) if unconditional else None
        if guide:  # one pass over [conditional, unconditional]
            cognition = torch.cat([cognition, cognition])
            extra = None if extra is None else torch.cat([extra, extra])
            drop = torch.arange(2 * b, device=x.device) >= b
        self.scheduler.set_timesteps(self.cfg.ddim_steps)
        for t in self.scheduler.timesteps:
            steps = t.to(x.device).expand(cognition.shape[0])
            if guide:
                eps_c, eps_u = self.dit(torch.cat([x, x]), steps, cognition, extra, drop).chunk(2)
                eps = eps_u + scale * (eps_c - eps_u)
            else:
                eps = self.dit(x, steps, cognition, extra, drop)
            x = self.scheduler.step(eps, t, x, eta=0.0).prev_sample
        return x

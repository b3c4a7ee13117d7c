"""Train-time image augmentation for MobileManiVLA: random shifts of every camera,
colour jitter of RGB images.

Evaluation rooms are unseen, so the policy must not key on the exact framing or the colours of the training
rooms. A shift (DrQ-style: replicate-pad by `shift` pixels, crop back at a random offset) is drawn per sample
and physical camera, so a camera's RGB and depth images stay aligned; brightness, contrast and saturation
factors are drawn per sample and RGB image. Depth images keep their values:
they encode metric distance, not appearance.
"""

from __future__ import annotations

from dataclasses import dataclass

import torch


@dataclass
class AugmentCfg:
    """Defaults are the CPU recipe's (conf/vla/train/cpu.yaml); zeros turn a part off."""

    shift: int = 4  # max translation in pixels at the model's image size
    brightness: float = 0.2  # RGB scaled by a factor in [1 - b, 1 + b]
    contrast: float = 0.2  # RGB pulled to / pushed from its mean by a factor in [1 - c, 1 + c]
    saturation: float = 0.2  # RGB blended with its grey image by a factor in [1 - s, 1 + s]
    # Share of RGB images passed through a random 3x3 convolution (Lee et al. 2020, network randomisation):
    # new colours and textures for every surface, which colour jitter alone cannot give a room.
    random_conv: float = 0.0

    @property
    def enabled(self) -> bool:
        return (
            self.shift > 0
            or self.brightness > 0
            or self.contrast > 0
            or self.saturation > 0
            or self.random_conv > 0
        )


def _factor(amount: float, shape: tuple[int, ...], like: torch.Tensor) -> torch.Tensor:
    return 1.0 + (torch.rand(shape, device=like.device, dtype=like.dtype) * 2 - 1) * amount


def shift_images(images: torch.Tensor, offsets: torch.Tensor) -> torch.Tensor:
    """(N, C, H, W) images translated by integer (dx, dy) pixel offsets (N, 2), edges replicated."""
    n, _, h, w = images.shape
    ys = torch.arange(h, device=images.device).view(1, h, 1) - offsets[:, 1].view(n, 1, 1)
    xs = torch.arange(w, device=images.device).view(1, 1, w) - offsets[:, 0].view(n, 1, 1)
    index = ys.clamp(0, h - 1) * w + xs.clamp(0, w - 1)  # (N, H, W) source pixel of every output pixel
    flat = images.flatten(2)
    return flat.gather(2, index.flatten(1).unsqueeze(1).expand(-1, images.shape[1], -1)).view_as(images)


def jitter_colour(rgb: torch.Tensor, cfg: AugmentCfg) -> torch.Tensor:
    """(N, 3, H, W) in [0, 1] -> brightness, contrast and saturation jittered, clamped to [0, 1]."""
    shape = (rgb.shape[0], 1, 1, 1)
    out = rgb
    if cfg.brightness > 0:
        out = out * _factor(cfg.brightness, shape, out)
    if cfg.contrast > 0:
        mean = out.mean(dim=(1, 2, 3), keepdim=True)
        out = (out - mean) * _factor(cfg.contrast, shape, out) + mean
    if cfg.saturation > 0:
        grey = (out * torch.tensor([0.299, 0.587, 0.114], device=out.device).view(1, 3, 1, 1)).sum(
            1, keepdim=True
        )
        out = (out - grey) * _factor(cfg.saturation, shape, out) + grey
    return out.clamp(0.0, 1.0)


def random_convolution(rgb: torch.Tensor, share: float) -> torch.Tensor:
    """(N, 3, H, W) in [0, 1] -> a `share` of the images convolved with their own random 3x3 kernel (3 -> 3
    channels, Xavier-normal, edges replicated), each rescaled to [0, 1]; the rest unchanged."""
    n = rgb.shape[0]
    chosen = torch.rand(n, device=rgb.device) < share
    if not chosen.any():
        return rgb
    picked = rgb[chosen]
    m = picked.shape[0]
    # Xavier-normal: fan-in = fan-out = 3 channels x 3 x 3
    kernels = torch.randn(m * 3, 3, 3, 3, device=rgb.device, dtype=rgb.dtype) / 27**0.5
    padded = torch.nn.functional.pad(
        picked.reshape(1, m * 3, *picked.shape[2:]), (1, 1, 1, 1), mode="replicate"
    )
    out = torch.nn.functional.conv2d(padded, kernels, groups=m).view_as(picked)
    low = out.amin(dim=(1, 2, 3), keepdim=True)
    high = out.amax(dim=(1, 2, 3), keepdim=True)
    result = rgb.clone()
    result[chosen] = (out - low) / (high - low).clamp(min=1e-6)
    return result


def augment_images(pixel_values: torch.Tensor, cameras: list[str], cfg: AugmentCfg) -> torch.Tensor:
    """(B, K, 3, S, S) batch images for `cameras` (names like head_rgb, wrist_depth) -> augmented copy."""
    if not cfg.enabled:
        return pixel_values
    out = pixel_values.clone()
    batch = pixel_values.shape[0]
    for camera in sorted({c.split("_")[0] for c in cameras}):
        views = [k for k, c in enumerate(cameras) if c.split("_")[0] == camera]
        if cfg.shift > 0:
            offsets = torch.randint(-cfg.shift, cfg.shift + 1, (batch, 2), device=out.device)
            for k in views:
                out[:, k] = shift_images(out[:, k], offsets)
    for k, camera in enumerate(cameras):
        if camera.endswith("_rgb"):
            out[:, k] = jitter_colour(out[:, k], cfg)
            if cfg.random_conv > 0:
                out[:, k] = random_convolution(out[:, k], cfg.random_conv)
    return out

"""Depth buffer -> metric depth -> ray distance -> 8-bit depth image.

MuJoCo's offscreen depth buffer (reversed Z, `mjDEPTH_ZEROFAR`) holds d = near (far - z) / (z (far - near))
for a point at z-depth z (distance along the optical axis). The reference stores the *ray* distance from the
camera centre (Isaac Lab `distance_to_camera`), which for a pinhole camera with focal
length f (pixels) and principal point c is z * sqrt(1 + ((u - cx) / f)^2 + ((v - cy) / f)^2) at pixel centre
(u, v). MuJoCo cameras have square pixels: f = (H / 2) / tan(fovy / 2) for both axes, c = (W / 2, H / 2).
"""

from __future__ import annotations

import math

import numpy as np


def focal_length(height: int, fovy_deg: float) -> float:
    return 0.5 * height / math.tan(math.radians(fovy_deg) / 2.0)


def ray_factor(width: int, height: int, fovy_deg: float) -> np.ndarray:
    """(H, W) multipliers turning z-depth into ray distance."""
    f = focal_length(height, fovy_deg)
    u = (np.arange(width) + 0.5 - width / 2.0) / f
    v = (np.arange(height) + 0.5 - height / 2.0) / f
    return np.sqrt(1.0 + u[None, :] ** 2 + v[:, None] ** 2).astype(np.float32)


def z_depth_from_buffer(buffer: np.ndarray, near: float, far: float) -> np.ndarray:
    """Invert the reversed-Z mapping; the far plane (d = 0, nothing drawn) comes out as `far`."""
    return (near * far / (near + buffer.astype(np.float64) * (far - near))).astype(np.float32)


def depth_to_uint8(distance: np.ndarray, clip: float) -> np.ndarray:
    """Clip to [0, clip] m and scale to 0–255, as the reference's depth videos."""
    return np.round(np.clip(distance, 0.0, clip) * (255.0 / clip)).astype(np.uint8)

"""Procedural texture images (numpy, deterministic from an rng) and the scene's material cache.

Patterns: wood grain, floor planks, tiles with grout, bricks, speckle (carpet, concrete, asphalt), and
MuJoCo's builtin checker and gradient. Colours are multiplied onto a grey-level pattern, so one pattern
serves any tint.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

SIZE = 128
Colour = Sequence[float]


def _smooth_noise(rng: np.random.Generator, cells: int) -> np.ndarray:
    """Value noise: a coarse random grid bilinearly upsampled to SIZE x SIZE, in [0, 1]."""
    grid = rng.random((cells + 1, cells + 1))
    t = np.linspace(0.0, cells, SIZE, endpoint=False)
    i, f = t.astype(int), t - t.astype(int)
    rows = grid[i] * (1 - f)[:, None] + grid[i + 1] * f[:, None]
    return rows[:, i] * (1 - f)[None, :] + rows[:, i + 1] * f[None, :]


def _grain(rng: np.random.Generator, stripes: float) -> np.ndarray:
    """Wood-like rings: stripes along x distorted by smooth noise, in [0, 1]."""
    x = np.linspace(0.0, 1.0, SIZE, endpoint=False)[None, :]
    warp = _smooth_noise(rng, 4) * 2.5 + _smooth_noise(rng, 16) * 0.4
    return 0.5 + 0.5 * np.sin(2 * np.pi * (stripes * x + warp))


def wood(rng: np.random.Generator) -> np.ndarray:
    return 0.78 + 0.22 * _grain(rng, rng.uniform(6, 12))


def planks(rng: np.random.Generator, rows: int = 4) -> np.ndarray:
    """Floor boards: `rows` bands of wood grain, each with its own tint and a dark seam."""
    level = 0.8 + 0.2 * _grain(rng, rng.uniform(2, 4)).T
    band = SIZE // rows
    for r in range(rows):
        level[r * band : (r + 1) * band] *= rng.uniform(0.85, 1.05)
        level[r * band] *= 0.55
    return level


def tiles(rng: np.random.Generator, count: int = 4, grout: float = 0.55) -> np.ndarray:
    """Square tiles with slightly varying brightness and grout lines."""
    cell = SIZE // count
    shade = rng.uniform(0.9, 1.0, (count, count)).repeat(cell, 0).repeat(cell, 1)
    shade = shade * (0.97 + 0.03 * _smooth_noise(rng, 8))
    lines = (np.arange(SIZE) % cell) < 3
    shade[lines, :] = grout
    shade[:, lines] = grout
    return shade


def bricks(rng: np.random.Generator, rows: int = 8) -> np.ndarray:
    """Running-bond bricks: alternate rows offset by half a brick, mortar in between."""
    height, width = SIZE // rows, SIZE // 4
    level = np.empty((SIZE, SIZE))
    for r in range(rows):
        offset = (width // 2) * (r % 2)
        for c in range(-1, 5):
            x0, x1 = max(0, c * width + offset), min(SIZE, (c + 1) * width + offset)
            if x1 > x0:
                level[r * height : (r + 1) * height, x0:x1] = rng.uniform(0.75, 1.0)
        level[r * height : r * height + 2] = 0.45
        for c in range(5):
            x = c * width + offset
            if x < SIZE:
                level[r * height : (r + 1) * height, x : x + 2] = 0.45
    return level * (0.92 + 0.08 * _smooth_noise(rng, 32))


def speckle(rng: np.random.Generator, strength: float = 0.15) -> np.ndarray:
    """Carpet, concrete or asphalt: fine noise over blotches."""
    fine = rng.random((SIZE, SIZE))
    return 1.0 - strength * (0.6 * fine + 0.4 * _smooth_noise(rng, 8))


PATTERNS = {"wood": wood, "planks": planks, "tiles": tiles, "bricks": bricks, "speckle": speckle}


class Materials:
    """Creates and caches `scene/` materials on a spec."""

    def __init__(self, spec: mujoco.MjSpec, rng: np.random.Generator) -> None:
        self.spec, self.rng, self._count = spec, rng, 0

    def _name(self, kind: str) -> str:
        self._count += 1
        return f"scene/{kind}{self._count}"

    def textured(self, pattern: str, colour: Colour, per_metre: float = 1.0, shininess: float = 0.1) -> str:
        """A material tiling the pattern `per_metre` times per metre on any geom size (texuniform)."""
        level = np.clip(PATTERNS[pattern](self.rng), 0.0, 1.0)
        image = (level[..., None] * np.asarray(colour[:3])[None, None, :] * 255).astype(np.uint8)
        name = self._name(pattern)
        texture = self.spec.add_texture(
            name=name, type=mujoco.mjtTexture.mjTEXTURE_2D, width=SIZE, height=SIZE, nchannel=3
        )
        texture.data = image.tobytes()
        return self._material(name, name, per_metre, shininess)

    def checker(self, colour1: Colour, colour2: Colour, per_metre: float) -> str:
        name = self._builtin("checker", mujoco.mjtBuiltin.mjBUILTIN_CHECKER, colour1, colour2)
        return self._material(name, name, per_metre / 2, 0.3)

    def gradient(self, top: Colour, bottom: Colour, emission: float = 0.0) -> str:
        """A vertical gradient stretched once over the geom (sky backdrops, pictures)."""
        name = self._builtin("gradient", mujoco.mjtBuiltin.mjBUILTIN_GRADIENT, top, bottom)
        material = self.spec.add_material(name=name, textures=["", name], emission=emission)
        return material.name

    def _builtin(self, kind: str, builtin: mujoco.mjtBuiltin, colour1: Colour, colour2: Colour) -> str:
        """A MuJoCo builtin two-colour texture; returns its name."""
        name = self._name(kind)
        self.spec.add_texture(
            name=name,
            type=mujoco.mjtTexture.mjTEXTURE_2D,
            builtin=builtin,
            rgb1=list(colour1[:3]),
            rgb2=list(colour2[:3]),
            width=SIZE,
            height=SIZE,
        )
        return name

    def emissive(self, colour: Colour, emission: float = 0.8) -> str:
        name = self._name("lamp")
        self.spec.add_material(name=name, rgba=list(colour[:3]) + [1.0], emission=emission)
        return name

    def _material(self, name: str, texture: str, per_metre: float, shininess: float) -> str:
        self.spec.add_material(
            name=name,
            textures=["", texture],
            texrepeat=[per_metre, per_metre],
            texuniform=True,
            shininess=shininess,
            specular=0.2,
        )
        return name

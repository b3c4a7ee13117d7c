"""Room styles: what floors, walls, lights and furniture a kitchen, bedroom, office, hospital, warehouse or
parking lot draws from. `make_palette` turns a style into concrete materials for one placement.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mobilemani_rl.assets.scenes.furniture import Colour, Palette
from mobilemani_rl.assets.scenes.textures import Materials


@dataclass(frozen=True)
class Style:
    name: str
    floors: tuple[str, ...]  # texture patterns ("checker" = MuJoCo builtin)
    floor_colours: tuple[Colour, ...]
    wall_colours: tuple[Colour, ...]
    wall_patterns: tuple[str, ...]  # "plain" = untextured paint
    height: tuple[float, float]  # ceiling height range (m)
    light: Colour  # lamp colour (warm or cool)
    furniture: tuple[str, ...]  # FURNITURE keys, repeated to weight them
    accents: tuple[Colour, ...]


WARM, COOL, NEUTRAL = (1.0, 0.88, 0.72, 1.0), (0.85, 0.92, 1.0, 1.0), (1.0, 0.97, 0.92, 1.0)
PASTELS = (
    (0.93, 0.9, 0.82, 1.0),
    (0.85, 0.9, 0.86, 1.0),
    (0.82, 0.87, 0.93, 1.0),
    (0.95, 0.85, 0.8, 1.0),
    (0.9, 0.9, 0.9, 1.0),
    (0.96, 0.93, 0.7, 1.0),
)
BRIGHT = (
    (0.8, 0.2, 0.15, 1.0),
    (0.15, 0.45, 0.75, 1.0),
    (0.9, 0.7, 0.1, 1.0),
    (0.2, 0.6, 0.3, 1.0),
    (0.55, 0.3, 0.6, 1.0),
    (0.95, 0.5, 0.2, 1.0),
    (0.1, 0.1, 0.12, 1.0),
    (0.9, 0.9, 0.88, 1.0),
)

INDOOR_STYLES: dict[str, Style] = {
    "kitchen": Style(
        "kitchen",
        ("tiles", "checker", "planks"),
        ((0.9, 0.88, 0.82, 1.0), (0.75, 0.72, 0.7, 1.0), (0.55, 0.4, 0.3, 1.0)),
        PASTELS,
        ("plain", "tiles"),
        (2.5, 2.9),
        WARM,
        ("cabinet", "cabinet", "appliance", "shelf", "plant", "dining_set", "chair"),
        BRIGHT,
    ),
    "bedroom": Style(
        "bedroom",
        ("planks", "speckle", "planks"),
        ((0.7, 0.5, 0.35, 1.0), (0.6, 0.55, 0.65, 1.0), (0.85, 0.7, 0.5, 1.0)),
        PASTELS + ((0.7, 0.78, 0.9, 1.0),),
        ("plain", "plain", "speckle"),
        (2.5, 2.8),
        WARM,
        ("bed", "nightstand", "wardrobe", "plant", "sofa", "floor_lamp", "shelf"),
        BRIGHT,
    ),
    "office": Style(
        "office",
        ("speckle", "planks", "tiles"),
        ((0.35, 0.38, 0.45, 1.0), (0.5, 0.5, 0.48, 1.0), (0.7, 0.6, 0.45, 1.0)),
        ((0.92, 0.92, 0.9, 1.0), (0.8, 0.84, 0.88, 1.0), (0.9, 0.88, 0.8, 1.0)),
        ("plain", "plain", "bricks"),
        (2.6, 3.2),
        NEUTRAL,
        ("desk", "desk", "shelf", "plant", "cabinet", "chair", "floor_lamp"),
        BRIGHT,
    ),
    "hospital": Style(
        "hospital",
        ("tiles", "checker", "speckle"),
        ((0.85, 0.9, 0.9, 1.0), (0.75, 0.85, 0.8, 1.0), (0.88, 0.88, 0.92, 1.0)),
        ((0.88, 0.95, 0.93, 1.0), (0.95, 0.95, 0.97, 1.0), (0.85, 0.9, 0.97, 1.0)),
        ("plain", "tiles"),
        (2.7, 3.0),
        COOL,
        ("hospital_bed", "curtain", "cabinet", "chair", "plant", "appliance"),
        ((0.3, 0.6, 0.7, 1.0), (0.6, 0.75, 0.9, 1.0), (0.9, 0.9, 0.95, 1.0), (0.4, 0.7, 0.5, 1.0)),
    ),
    "warehouse": Style(
        "warehouse",
        ("speckle", "speckle", "checker"),
        ((0.55, 0.55, 0.52, 1.0), (0.45, 0.47, 0.5, 1.0), (0.6, 0.58, 0.5, 1.0)),
        ((0.7, 0.4, 0.3, 1.0), (0.6, 0.62, 0.65, 1.0), (0.8, 0.78, 0.72, 1.0)),
        ("bricks", "plain", "speckle"),
        (4.0, 6.0),
        COOL,
        ("pallet_rack", "pallet_rack", "box_stack", "barrels", "box_stack"),
        ((0.15, 0.3, 0.65, 1.0), (0.9, 0.45, 0.1, 1.0), (0.6, 0.45, 0.28, 1.0)),
    ),
}
PARKING_LOT = "parking_lot"


def pick(rng: np.random.Generator, options: tuple) -> object:
    return options[int(rng.integers(len(options)))]


def _shade(rng: np.random.Generator, colour: Colour, spread: float = 0.08) -> Colour:
    scale = 1.0 + rng.uniform(-spread, spread, 3)
    return (*np.clip(np.asarray(colour[:3]) * scale, 0.0, 1.0).tolist(), 1.0)


def make_palette(style: Style, materials: Materials, rng: np.random.Generator) -> Palette:
    wood_tone = pick(rng, ((0.75, 0.55, 0.35, 1.0), (0.55, 0.38, 0.25, 1.0), (0.85, 0.72, 0.55, 1.0)))
    return Palette(
        wood=materials.textured("wood", _shade(rng, wood_tone), per_metre=1.5),
        dark_wood=materials.textured("wood", _shade(rng, (0.35, 0.24, 0.16, 1.0)), per_metre=2.0),
        fabric=_shade(rng, pick(rng, style.accents), 0.15),
        metal=_shade(rng, (0.6, 0.62, 0.65, 1.0)),
        white=_shade(rng, (0.93, 0.93, 0.9, 1.0), 0.04),
        accents=tuple(_shade(rng, c, 0.15) for c in style.accents),
        lamp=materials.emissive(style.light, 0.9),
    )


def floor_material(style: Style, materials: Materials, rng: np.random.Generator) -> str:
    pattern = pick(rng, style.floors)
    colour = _shade(rng, pick(rng, style.floor_colours))
    if pattern == "checker":
        return materials.checker(
            colour, _shade(rng, (0.25, 0.25, 0.27, 1.0)), per_metre=rng.uniform(2.0, 3.5)
        )
    per_metre = {"tiles": rng.uniform(0.6, 1.2), "planks": rng.uniform(0.8, 1.2), "speckle": 2.0}[pattern]
    return materials.textured(pattern, colour, per_metre)


def wall_material(style: Style, materials: Materials, rng: np.random.Generator) -> str | Colour:
    pattern = pick(rng, style.wall_patterns)
    colour = _shade(rng, pick(rng, style.wall_colours), 0.05)
    if pattern == "plain":
        return colour
    return materials.textured(pattern, colour, {"tiles": 2.5, "bricks": 1.0, "speckle": 1.0}[pattern])

"""Furniture and clutter from primitives. Each piece is built in its own frame: footprint centred on the
origin, standing on z = 0, front toward -y; `FURNITURE` records the footprint half extents used for layout.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from mobilemani_rl.assets.scenes.canvas import Canvas, Paint

Colour = tuple[float, float, float, float]


@dataclass(frozen=True)
class Palette:
    """The materials and colours one room draws from."""

    wood: Paint
    dark_wood: Paint
    fabric: Colour
    metal: Colour
    white: Colour
    accents: tuple[Colour, ...]
    lamp: Paint  # emissive


def _pick(rng: np.random.Generator, colours: tuple[Colour, ...]) -> Colour:
    return colours[int(rng.integers(len(colours)))]


def _legs(c: Canvas, hx: float, hy: float, height: float, radius: float, paint: Paint) -> None:
    for sx in (-1, 1):
        for sy in (-1, 1):
            c.cylinder((sx * (hx - radius), sy * (hy - radius), height / 2), radius, height / 2, paint)


def table(
    c: Canvas, hx: float, hy: float, height: float, top: Paint, legs: Paint, thickness: float = 0.03
) -> None:
    c.box((0, 0, height - thickness / 2), (hx, hy, thickness / 2), top)
    _legs(c, hx - 0.03, hy - 0.03, height - thickness, 0.025, legs)


def chair(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    seat = _pick(rng, p.accents) if rng.random() < 0.5 else p.wood
    _legs(c, 0.2, 0.2, 0.45, 0.015, p.metal)
    c.box((0, 0, 0.47), (0.22, 0.22, 0.025), seat)
    c.box((0, 0.2, 0.75), (0.22, 0.02, 0.25), seat)


def dining_set(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    table(c, 0.6, 0.4, 0.75, p.wood, p.dark_wood)
    for sx in (-0.3, 0.3):
        chair(c.item(sx, -0.55, np.pi), rng, p)
    c.cylinder((0.1, 0.05, 0.8), 0.05, 0.05, _pick(rng, p.accents))  # a vase


def shelf(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    """Bookcase with rows of books and boxes."""
    width, depth, height = 0.4, 0.15, 0.9
    frame = p.wood if rng.random() < 0.6 else p.white
    for sx in (-1, 1):
        c.box((sx * width, 0, height), (0.015, depth, height), frame)
    c.box((0, depth - 0.01, height), (width, 0.01, height), frame)
    for level in range(5):
        z = 0.05 + level * 0.42
        c.box((0, 0, z), (width, depth, 0.015), frame)
        x = -width + 0.03
        while x < width - 0.08 and level < 4:
            thick = rng.uniform(0.015, 0.04)
            tall = rng.uniform(0.12, 0.3)
            c.box(
                (x + thick, rng.uniform(-0.02, 0.02), z + 0.015 + tall / 2),
                (thick, 0.1, tall / 2),
                _pick(rng, p.accents),
            )
            x += 2 * thick + rng.uniform(0.0, 0.06)


def cabinet(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    """Low cupboard / kitchen counter with two doors and handles."""
    body = p.white if rng.random() < 0.5 else p.wood
    c.box((0, 0, 0.45), (0.5, 0.28, 0.45), body)
    c.box((0, 0, 0.915), (0.52, 0.3, 0.015), p.dark_wood)
    for sx in (-0.25, 0.25):
        c.box((sx, -0.285, 0.45), (0.235, 0.008, 0.4), body)
        c.capsule((sx - 0.04 * np.sign(sx), -0.3, 0.55), (sx - 0.04 * np.sign(sx), -0.3, 0.7), 0.008, p.metal)
    for _ in range(int(rng.integers(1, 4))):
        c.cylinder(
            (rng.uniform(-0.4, 0.4), rng.uniform(-0.1, 0.15), 0.98),
            rng.uniform(0.03, 0.07),
            0.05,
            _pick(rng, p.accents),
        )


def appliance(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    """Tall fridge or wardrobe-like column with a door seam and a long handle."""
    colour = p.white if rng.random() < 0.6 else p.metal
    c.box((0, 0, 0.95), (0.35, 0.33, 0.95), colour)
    c.box((0, -0.335, 1.3), (0.34, 0.005, 0.003), p.metal)
    c.capsule((-0.28, -0.36, 0.7), (-0.28, -0.36, 1.2), 0.012, p.metal)


def wardrobe(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    c.box((0, 0, 1.0), (0.55, 0.3, 1.0), p.wood)
    c.box((0, -0.302, 1.0), (0.003, 0.003, 0.95), p.dark_wood)
    for sx in (-0.06, 0.06):
        c.capsule((sx, -0.32, 0.9), (sx, -0.32, 1.1), 0.01, p.metal)


def plant(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    pot_r = rng.uniform(0.12, 0.18)
    c.cylinder((0, 0, 0.17), pot_r, 0.17, _pick(rng, p.accents))
    green = (rng.uniform(0.1, 0.25), rng.uniform(0.4, 0.6), rng.uniform(0.1, 0.25), 1.0)
    height = rng.uniform(0.6, 1.2)
    c.capsule((0, 0, 0.3), (0, 0, height), 0.02, (0.35, 0.25, 0.15, 1.0))
    for _ in range(int(rng.integers(3, 7))):
        c.ellipsoid(
            (rng.uniform(-0.12, 0.12), rng.uniform(-0.12, 0.12), height + rng.uniform(-0.25, 0.1)),
            (rng.uniform(0.1, 0.2), rng.uniform(0.1, 0.2), rng.uniform(0.08, 0.15)),
            green,
        )


def bed(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    """Double bed, head board at +y."""
    c.box((0, 0, 0.2), (0.75, 1.0, 0.2), p.wood)
    c.box((0, -0.05, 0.47), (0.72, 0.93, 0.08), p.white)
    c.box((0, -0.25, 0.56), (0.74, 0.72, 0.03), _pick(rng, p.accents))
    c.box((0, 0.99, 0.55), (0.75, 0.03, 0.55), p.dark_wood)
    for sx in (-0.35, 0.35):
        c.ellipsoid((sx, 0.75, 0.6), (0.28, 0.12, 0.07), p.white)


def nightstand(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    c.box((0, 0, 0.25), (0.22, 0.2, 0.25), p.wood)
    c.cylinder((0, 0.05, 0.55), 0.06, 0.05, p.metal)
    c.cylinder((0, 0.05, 0.7), 0.12, 0.08, p.lamp)


def sofa(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    cloth = _pick(rng, p.accents)
    c.box((0, 0, 0.22), (0.9, 0.4, 0.2), cloth)
    c.box((0, 0.3, 0.55), (0.9, 0.1, 0.3), cloth)
    for sx in (-1, 1):
        c.box((sx * 0.85, 0, 0.4), (0.08, 0.4, 0.18), cloth)
    for sx in (-0.45, 0.45):
        c.box((sx, -0.02, 0.47), (0.4, 0.3, 0.06), p.fabric)


def desk(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    """Office desk with a monitor, keyboard and an office chair in front."""
    table(c, 0.7, 0.35, 0.74, p.wood if rng.random() < 0.5 else p.white, p.metal)
    c.box((0, 0.15, 1.0), (0.3, 0.015, 0.18), (0.05, 0.05, 0.06, 1.0))
    c.box((0, 0.17, 0.8), (0.03, 0.02, 0.06), p.metal)
    c.box((0, -0.1, 0.75), (0.22, 0.07, 0.01), (0.15, 0.15, 0.16, 1.0))
    c.box((0.45, 0.0, 0.78), (0.1, 0.14, 0.04), _pick(rng, p.accents))
    seat = c.item(0, -0.6)
    seat.cylinder((0, 0, 0.23), 0.03, 0.2, p.metal)
    seat.cylinder((0, 0, 0.03), 0.25, 0.02, p.metal)
    seat.box((0, 0, 0.47), (0.24, 0.24, 0.05), p.fabric)
    seat.box((0, -0.22, 0.8), (0.22, 0.03, 0.28), p.fabric)


def box_stack(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    """Cardboard boxes stacked loosely."""
    z = 0.0
    for _ in range(int(rng.integers(2, 5))):
        half = (rng.uniform(0.18, 0.35), rng.uniform(0.15, 0.28), rng.uniform(0.1, 0.22))
        tint = rng.uniform(0.85, 1.1)
        c.box(
            (rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), z + half[2]),
            half,
            (0.6 * tint, 0.45 * tint, 0.28 * tint, 1.0),
            yaw=rng.uniform(-0.3, 0.3),
        )
        z += 2 * half[2]


def pallet_rack(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    """Warehouse rack: orange beams, blue uprights, boxes on three levels."""
    upright, beam = (0.1, 0.2, 0.6, 1.0), (0.9, 0.45, 0.1, 1.0)
    for sx in (-0.9, 0.9):
        for sy in (-0.4, 0.4):
            c.box((sx, sy, 1.25), (0.03, 0.03, 1.25), upright)
    for z in (0.15, 1.05, 1.95):
        for sy in (-0.4, 0.4):
            c.box((0, sy, z), (0.9, 0.03, 0.05), beam)
        c.box((0, 0, z + 0.06), (0.88, 0.4, 0.01), (0.55, 0.45, 0.3, 1.0))
        for x in np.linspace(-0.6, 0.6, int(rng.integers(1, 4))):
            if rng.random() < 0.85:
                box_stack(c.item(x + rng.uniform(-0.1, 0.1), 0, z=z + 0.07), rng, p)


def barrels(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    colour = _pick(rng, ((0.15, 0.3, 0.65, 1.0), (0.7, 0.15, 0.1, 1.0), (0.2, 0.45, 0.2, 1.0)))
    for x, y in ((-0.3, 0.0), (0.3, 0.0), (0.0, 0.45))[: int(rng.integers(1, 4))]:
        c.cylinder((x, y - 0.15, 0.45), 0.28, 0.45, colour)
        c.cylinder((x, y - 0.15, 0.9), 0.285, 0.01, p.metal)


def hospital_bed(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    _legs(c, 0.45, 0.95, 0.45, 0.02, p.metal)
    c.box((0, 0, 0.5), (0.45, 1.0, 0.06), p.white)
    c.box((0, -0.1, 0.57), (0.44, 0.85, 0.02), _pick(rng, p.accents))
    c.box((0, 0.75, 0.62), (0.3, 0.12, 0.05), p.white)
    for sx in (-1, 1):
        c.box((sx * 0.47, 0.2, 0.7), (0.01, 0.5, 0.1), p.metal)
    c.box((0, 1.0, 0.75), (0.46, 0.02, 0.3), p.metal)
    stand = c.item(0.6, 0.8)
    stand.capsule((0, 0, 0.02), (0, 0, 1.8), 0.012, p.metal)
    stand.ellipsoid((0.08, 0, 1.65), (0.05, 0.02, 0.1), (0.85, 0.9, 0.95, 0.7))


def curtain(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    """Hospital privacy screen: frame with a light fabric panel."""
    cloth = _pick(rng, ((0.7, 0.85, 0.85, 1.0), (0.85, 0.8, 0.65, 1.0), (0.75, 0.8, 0.9, 1.0)))
    c.box((0, 0, 1.05), (0.8, 0.01, 0.75), cloth)
    for sx in (-0.82, 0.82):
        c.capsule((sx, 0, 0.05), (sx, 0, 1.85), 0.015, p.metal)
    c.capsule((-0.82, 0, 1.85), (0.82, 0, 1.85), 0.015, p.metal)


def floor_lamp(c: Canvas, rng: np.random.Generator, p: Palette) -> None:
    c.cylinder((0, 0, 0.02), 0.15, 0.02, p.metal)
    c.capsule((0, 0, 0.04), (0, 0, 1.5), 0.012, p.metal)
    c.cylinder((0, 0, 1.55), 0.17, 0.12, p.lamp)


@dataclass(frozen=True)
class Furniture:
    build: Callable[[Canvas, np.random.Generator, Palette], None]
    half_x: float  # footprint half extents in the piece's frame
    half_y: float


FURNITURE: dict[str, Furniture] = {
    "dining_set": Furniture(dining_set, 0.65, 0.85),
    "chair": Furniture(chair, 0.25, 0.25),
    "shelf": Furniture(shelf, 0.42, 0.16),
    "cabinet": Furniture(cabinet, 0.52, 0.3),
    "appliance": Furniture(appliance, 0.36, 0.36),
    "wardrobe": Furniture(wardrobe, 0.56, 0.32),
    "plant": Furniture(plant, 0.25, 0.25),
    "bed": Furniture(bed, 0.76, 1.02),
    "nightstand": Furniture(nightstand, 0.23, 0.21),
    "sofa": Furniture(sofa, 0.95, 0.42),
    "desk": Furniture(desk, 0.72, 0.9),
    "box_stack": Furniture(box_stack, 0.4, 0.35),
    "pallet_rack": Furniture(pallet_rack, 0.95, 0.45),
    "barrels": Furniture(barrels, 0.6, 0.6),
    "hospital_bed": Furniture(hospital_bed, 0.7, 1.02),
    "curtain": Furniture(curtain, 0.85, 0.03),
    "floor_lamp": Furniture(floor_lamp, 0.18, 0.18),
}


def support_table(
    c: Canvas,
    hx: float,
    hy: float,
    height: float,
    style: str,
    p: Palette,
    rng: np.random.Generator,
    below_floor: float = 0.0,
) -> None:
    """The visible table under a tabletop object, top surface at `height` (the invisible stage's top); its
    legs reach `below_floor` m under the floor, so that it still stands on the floor when raised that much."""
    counter = style == "kitchen" and height > 0.55  # chosen by the room's height, however far the legs go
    if below_floor > 0:
        c, height = c.item(0.0, 0.0, z=-below_floor), height + below_floor
    if counter:  # solid cabinets under a worktop
        c.box((0, 0, height - 0.02), (hx, hy, 0.02), p.dark_wood if rng.random() < 0.5 else p.white)
        c.box((0, 0.03, (height - 0.04) / 2), (hx - 0.02, hy - 0.03, (height - 0.04) / 2), p.wood)
        for x in np.arange(-hx + 0.25, hx - 0.1, 0.5):
            c.box((x, -hy - 0.002, height * 0.5), (0.23, 0.004, height * 0.4), p.white)
            c.capsule(
                (x + 0.15, -hy - 0.012, height * 0.75), (x + 0.15, -hy - 0.012, height * 0.85), 0.008, p.metal
            )
    elif style == "warehouse":  # a workbench: metal frame, wooden top, lower shelf
        table(c, hx, hy, height, p.wood, (0.25, 0.3, 0.35, 1.0), thickness=0.04)
        if height > 0.4:
            c.box((0, 0, 0.15), (hx - 0.04, hy - 0.04, 0.01), (0.3, 0.32, 0.35, 1.0))
    elif style == "hospital":
        table(c, hx, hy, height, p.white, p.metal)
    else:
        table(c, hx, hy, height, p.wood if rng.random() < 0.7 else p.white, p.dark_wood, thickness=0.04)

"""Indoor room shell in the room body's frame: the back wall's inner face at y = 0 (optionally with an opening
the object stands in), the room extending toward -y; floor, walls, ceiling, baseboards, windows, pictures and
ceiling lights.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mobilemani_rl.assets.scenes.canvas import Canvas, Paint
from mobilemani_rl.assets.scenes.styles import Style, floor_material, pick, wall_material
from mobilemani_rl.assets.scenes.textures import Materials

WALL = 0.1  # wall thickness
CEILING_GROUP = 1  # drawn by default; overview renders switch group 1 off to look into the room
CEILING = (0.95, 0.95, 0.93, 1.0)
SKY = ((0.55, 0.75, 0.95, 1.0), (0.85, 0.9, 0.95, 1.0))


@dataclass(frozen=True)
class RoomBox:
    x0: float
    x1: float
    depth: float  # the room spans y in [-depth, 0]
    height: float


@dataclass(frozen=True)
class Opening:
    """A hole in the back wall around a door or window; `thickness` is the back wall's depth there."""

    x0: float
    x1: float
    z0: float
    z1: float
    thickness: float


def build_shell(
    canvas: Canvas,
    room: RoomBox,
    style: Style,
    materials: Materials,
    rng: np.random.Generator,
    opening: Opening | None,
) -> Paint:
    """Floor, four walls, ceiling and baseboards; returns the wall paint for decorations to match."""
    x0, x1, d, h = room.x0, room.x1, room.depth, room.height
    cx, cy = (x0 + x1) / 2, -d / 2
    canvas.box((cx, cy, -0.02), ((x1 - x0) / 2, d / 2, 0.02), floor_material(style, materials, rng))
    ceiling = canvas.box((cx, cy, h + 0.03), ((x1 - x0) / 2 + WALL, d / 2 + WALL, 0.03), CEILING)
    ceiling.group = CEILING_GROUP
    walls = wall_material(style, materials, rng)
    accent = wall_material(style, materials, rng) if rng.random() < 0.5 else walls
    back_t = opening.thickness if opening else WALL
    _back_wall(canvas, room, accent, opening, back_t)
    canvas.box((cx, -d - WALL / 2, h / 2), ((x1 - x0) / 2 + WALL, WALL / 2, h / 2), walls)
    for x in (x0 - WALL / 2, x1 + WALL / 2):
        canvas.box((x, cy + back_t / 2, h / 2), (WALL / 2, d / 2 + back_t / 2, h / 2), walls)
    trim = pick(rng, ((0.95, 0.95, 0.93, 1.0), (0.35, 0.25, 0.2, 1.0), (0.3, 0.3, 0.32, 1.0)))
    canvas.box((cx, -d + 0.01, 0.05), ((x1 - x0) / 2, 0.01, 0.05), trim)
    for x in (x0 + 0.01, x1 - 0.01):
        canvas.box((x, cy, 0.05), (0.01, d / 2, 0.05), trim)
    return walls


def _back_wall(
    canvas: Canvas, room: RoomBox, paint: Paint, opening: Opening | None, thickness: float
) -> None:
    x0, x1, h = room.x0 - WALL, room.x1 + WALL, room.height
    y = thickness / 2
    if opening is None:
        canvas.box(((x0 + x1) / 2, y, h / 2), ((x1 - x0) / 2, y, h / 2), paint)
        return
    o = opening
    canvas.box(((x0 + o.x0) / 2, y, h / 2), ((o.x0 - x0) / 2, y, h / 2), paint)
    canvas.box(((o.x1 + x1) / 2, y, h / 2), ((x1 - o.x1) / 2, y, h / 2), paint)
    canvas.box(((o.x0 + o.x1) / 2, y, (o.z1 + h) / 2), ((o.x1 - o.x0) / 2, y, (h - o.z1) / 2), paint)
    if o.z0 > 0.0:
        canvas.box(((o.x0 + o.x1) / 2, y, o.z0 / 2), ((o.x1 - o.x0) / 2, y, o.z0 / 2), paint)
    frame = (0.92, 0.92, 0.9, 1.0)
    for x in (o.x0 + 0.02, o.x1 - 0.02):  # jambs and lintel
        canvas.box((x, y, (o.z0 + o.z1) / 2), (0.02, y + 0.01, (o.z1 - o.z0) / 2), frame)
    canvas.box(((o.x0 + o.x1) / 2, y, o.z1 - 0.02), ((o.x1 - o.x0) / 2, y + 0.01, 0.02), frame)


def build_beyond(
    canvas: Canvas,
    opening: Opening,
    style: Style,
    materials: Materials,
    rng: np.random.Generator,
    outdoors: bool,
) -> None:
    """What the opening shows: a sky-and-lawn backdrop for windows, a corridor for doors."""
    y0 = opening.thickness
    width = opening.x1 - opening.x0 + 1.5
    cx = (opening.x0 + opening.x1) / 2
    if outdoors:
        canvas.box((cx, y0 + 3.0, 2.5), (width + 2.0, 0.05, 3.5), materials.gradient(*SKY, emission=0.7))
        canvas.box((cx, y0 + 1.5, -0.01), (width + 2.0, 1.5, 0.01), (0.3, 0.5, 0.25, 1.0))
        return
    length, height = rng.uniform(1.5, 3.0), opening.z1 + 0.4
    canvas.box(
        (cx, y0 + length / 2, -0.02), (width / 2, length / 2, 0.02), floor_material(style, materials, rng)
    )
    far = wall_material(style, materials, rng)
    canvas.box((cx, y0 + length + WALL / 2, height / 2), (width / 2, WALL / 2, height / 2), far)
    for x in (cx - width / 2, cx + width / 2):
        canvas.box((x, y0 + length / 2, height / 2), (WALL / 2, length / 2, height / 2), far)
    ceiling = canvas.box((cx, y0 + length / 2, height + 0.02), (width / 2, length / 2, 0.02), CEILING)
    ceiling.group = CEILING_GROUP


def decorate_walls(
    canvas: Canvas, room: RoomBox, materials: Materials, rng: np.random.Generator, back_clear_above: float
) -> None:
    """Windows on the side walls, pictures on the side and back walls (the back one above the object)."""
    x0, x1, d, h = room.x0, room.x1, room.depth, room.height
    for x, inward in ((x0, 1.0), (x1, -1.0)):
        for _ in range(int(rng.integers(0, 3))):
            y = rng.uniform(-d + 0.8, -0.8)
            half_w, z0, z1 = (
                rng.uniform(0.35, 0.7),
                rng.uniform(0.8, 1.0),
                min(h - 0.3, rng.uniform(1.9, 2.3)),
            )
            canvas.box(
                (x + inward * 0.005, y, (z0 + z1) / 2),
                (0.01, half_w, (z1 - z0) / 2),
                materials.gradient(*SKY, emission=0.6),
            )
            for zz in (z0, z1, (z0 + z1) / 2):
                canvas.box((x + inward * 0.015, y, zz), (0.015, half_w, 0.02), (0.9, 0.9, 0.88, 1.0))
            canvas.box(
                (x + inward * 0.015, y, (z0 + z1) / 2), (0.015, 0.02, (z1 - z0) / 2), (0.9, 0.9, 0.88, 1.0)
            )
        if rng.random() < 0.7:
            _picture(
                canvas,
                (x + inward * 0.01, rng.uniform(-d + 0.6, -0.6), rng.uniform(1.4, 1.7)),
                True,
                materials,
                rng,
            )
    z = back_clear_above + rng.uniform(0.35, 0.6)
    if z < h - 0.35:
        _picture(canvas, (rng.uniform(-0.3, 0.3), -0.01, z), False, materials, rng)


def _picture(
    canvas: Canvas,
    pos: tuple[float, float, float],
    on_side: bool,
    materials: Materials,
    rng: np.random.Generator,
) -> None:
    w, hgt = rng.uniform(0.15, 0.35), rng.uniform(0.12, 0.25)
    colours = rng.uniform(0.1, 0.95, (2, 3))
    half = (0.01, w, hgt) if on_side else (w, 0.01, hgt)
    frame = tuple(h + 0.03 if h > 0.02 else h for h in half)
    canvas.box(pos, frame, (0.15, 0.12, 0.1, 1.0))
    offset = np.array([0.01, 0.0, 0.0]) if on_side else np.array([0.0, -0.01, 0.0])
    if on_side and pos[0] > 0:
        offset = -offset
    canvas.box(np.asarray(pos) + offset, half, materials.gradient(colours[0], colours[1]))


def add_ceiling_lights(
    body: mujoco.MjsBody, canvas: Canvas, room: RoomBox, style: Style, lamp: Paint, rng: np.random.Generator
) -> None:
    """One or two spot lights under emissive panels; colours follow the style (warm or cool)."""
    d, h = room.depth, room.height
    count = int(rng.integers(1, 3))
    colour = np.asarray(style.light[:3]) * rng.uniform(0.45, 0.7)
    for k in range(count):
        x = (room.x0 + room.x1) / 2 + rng.uniform(-0.8, 0.8)
        y = -d * (k + 1) / (count + 1)
        canvas.box((x, y, h - 0.01), (0.3, 0.3, 0.01), lamp)
        body.add_light(
            pos=[x, y, h - 0.05],
            dir=[0, 0, -1],
            type=mujoco.mjtLightType.mjLIGHT_SPOT,
            diffuse=colour.tolist(),
            specular=[0.1, 0.1, 0.1],
            cutoff=70.0,
            exponent=1.0,
            attenuation=[1.0, 0.0, 0.0],
            castshadow=True,
        )

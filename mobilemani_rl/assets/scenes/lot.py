"""Outdoor parking lot in the room body's frame: kerb line at y = 0 behind the car slot, asphalt toward -y,
sidewalk, building facades, lamp posts, trees, and parked cars in the neighbouring bays.
"""

from __future__ import annotations

import mujoco
import numpy as np

from mobilemani_rl.assets.scenes.canvas import Canvas
from mobilemani_rl.assets.scenes.layout import Rect
from mobilemani_rl.assets.scenes.styles import pick
from mobilemani_rl.assets.scenes.textures import Materials

CAR_COLOURS = (
    (0.75, 0.1, 0.1, 1.0),
    (0.1, 0.2, 0.55, 1.0),
    (0.85, 0.85, 0.85, 1.0),
    (0.1, 0.1, 0.1, 1.0),
    (0.5, 0.52, 0.55, 1.0),
    (0.2, 0.45, 0.3, 1.0),
    (0.9, 0.75, 0.2, 1.0),
)
BAY = 2.6  # parking bay width (m)


def parked_car(c: Canvas, rng: np.random.Generator) -> None:
    """A car pointing along y, footprint about 1.8 x 4.2 m."""
    paint = pick(rng, CAR_COLOURS)
    glass = (0.12, 0.15, 0.2, 1.0)
    c.box((0, 0, 0.6), (0.9, 2.1, 0.3), paint)
    c.box((0, 0.2, 1.1), (0.8, 1.1, 0.22), glass)
    c.box((0, 0.2, 1.34), (0.78, 1.0, 0.03), paint)
    for x in (-0.82, 0.82):
        for y in (-1.35, 1.4):
            c.tube((x - 0.1, y, 0.33), (x + 0.1, y, 0.33), 0.33, (0.05, 0.05, 0.05, 1.0))
    for x in (-0.6, 0.6):
        c.box((x, -2.1, 0.65), (0.15, 0.01, 0.06), (1.0, 1.0, 0.85, 1.0))


def lamp_post(c: Canvas, lamp: str) -> None:
    grey = (0.3, 0.32, 0.33, 1.0)
    c.tube((0, 0, 0), (0, 0, 5.0), 0.07, grey)
    c.capsule((0, 0, 5.0), (0, -0.8, 5.1), 0.05, grey)
    c.box((0, -0.9, 5.05), (0.15, 0.25, 0.05), lamp)


def tree(c: Canvas, rng: np.random.Generator) -> None:
    height = rng.uniform(2.5, 4.5)
    c.tube((0, 0, 0), (0, 0, height), rng.uniform(0.08, 0.15), (0.35, 0.25, 0.15, 1.0))
    green = (rng.uniform(0.1, 0.3), rng.uniform(0.35, 0.55), rng.uniform(0.1, 0.2), 1.0)
    for _ in range(4):
        c.sphere(
            (rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), height + rng.uniform(-0.3, 0.5)),
            rng.uniform(0.7, 1.2),
            green,
        )


def building(
    c: Canvas, x: float, width: float, y: float, materials: Materials, rng: np.random.Generator
) -> None:
    height = rng.uniform(6.0, 14.0)
    wall = materials.textured(
        str(pick(rng, ("bricks", "speckle", "tiles"))),
        pick(rng, ((0.7, 0.4, 0.3, 1.0), (0.85, 0.82, 0.75, 1.0), (0.55, 0.6, 0.65, 1.0))),
        per_metre=0.7,
    )
    c.box((x, y + 2.0, height / 2), (width / 2, 2.0, height / 2), wall)
    glass = pick(rng, ((0.25, 0.35, 0.5, 1.0), (0.15, 0.2, 0.25, 1.0), (0.5, 0.6, 0.7, 1.0)))
    for z in np.arange(1.2, height - 1.0, 3.0):
        for wx in np.arange(x - width / 2 + 1.0, x + width / 2 - 0.8, 1.8):
            c.box((wx, y - 0.01, z + 0.7), (0.5, 0.02, 0.6), glass)


def build_parking_lot(
    body: mujoco.MjsBody,
    canvas: Canvas,
    materials: Materials,
    rng: np.random.Generator,
    half_width: float,
    keep_out: list[Rect],
) -> None:
    """`half_width`: the object's half extent in x; `keep_out`: rectangles (room frame) nothing may enter."""
    asphalt = (*(np.array([0.32, 0.32, 0.34]) * rng.uniform(0.6, 1.4)), 1.0)
    canvas.box((0, -8.0, -0.02), (16.0, 8.0, 0.02), materials.textured("speckle", asphalt, 2.0))
    paving = pick(rng, ((0.72, 0.7, 0.66, 1.0), (0.6, 0.45, 0.4, 1.0), (0.55, 0.57, 0.6, 1.0)))
    pattern = str(pick(rng, ("tiles", "bricks")))
    canvas.box((0, 2.0, 0.07), (16.0, 2.0, 0.07), materials.textured(pattern, paving, 1.5))
    canvas.box((0, 0.0, 0.08), (16.0, 0.08, 0.08), (0.8, 0.8, 0.78, 1.0))
    line = (0.92, 0.92, 0.88, 1.0)
    bay = max(BAY, 2 * half_width + 0.8)
    for k in range(-4, 5):  # bay lines between the object's bay and its neighbours
        canvas.box(((k + 0.5) * bay, -2.5, 0.002), (0.06, 2.5, 0.002), line)
    canvas.box((0, -6.5, 0.002), (16.0, 0.08, 0.002), pick(rng, (line, (0.95, 0.8, 0.1, 1.0))))
    for k in (-3, -2, -1, 1, 2, 3):
        x = k * bay
        rect = Rect(x - 0.95, -4.4, x + 0.95, 0.0)
        if rng.random() < 0.75 and not any(rect.overlaps(r) for r in keep_out):
            parked_car(canvas.item(x + rng.uniform(-0.15, 0.15), -2.2, np.pi + rng.uniform(-0.05, 0.05)), rng)
    for k in range(-3, 4):  # cars across the street
        if rng.random() < 0.5:
            parked_car(canvas.item(k * BAY + rng.uniform(-0.3, 0.3), -10.0, rng.uniform(-0.05, 0.05)), rng)
    lamp = materials.emissive((1.0, 0.95, 0.8, 1.0), 1.0)
    for x in np.arange(-12.0, 12.1, rng.uniform(5.0, 8.0)):
        if abs(x) > half_width + 0.5:
            lamp_post(canvas.item(x, 0.6, np.pi), lamp)
    for x in np.arange(-10.0, 10.1, rng.uniform(3.0, 5.0)):
        if abs(x) > half_width + 1.0 and rng.random() < 0.7:
            tree(canvas.item(x + rng.uniform(-0.5, 0.5), 2.6), rng)
    x = -16.0
    while x < 16.0:
        width = rng.uniform(6.0, 12.0)
        building(canvas, x + width / 2, width, rng.uniform(4.0, 6.0), materials, rng)
        x += width + rng.uniform(0.0, 2.0)
    body.add_light(
        pos=[0, -4.0, 8.0],
        dir=[0.2, 0.3, -1.0],
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        diffuse=(np.array([1.0, 0.97, 0.9]) * rng.uniform(0.35, 0.6)).tolist(),
        castshadow=True,
    )

"""Furniture along the walls, never inside keep-out rectangles (the robot's corridor, the object's slot)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mobilemani_rl.assets.scenes.canvas import Canvas
from mobilemani_rl.assets.scenes.furniture import FURNITURE, Palette
from mobilemani_rl.assets.scenes.styles import pick

GAP = (0.05, 0.5)  # free space between neighbours (m)


@dataclass(frozen=True)
class Rect:
    x0: float
    y0: float
    x1: float
    y1: float

    def overlaps(self, other: Rect) -> bool:
        return self.x0 < other.x1 and other.x0 < self.x1 and self.y0 < other.y1 and other.y0 < self.y1


@dataclass(frozen=True)
class Wall:
    """A straight run of wall, in room coordinates: from `start` along `direction`, pieces face `inward`."""

    start: tuple[float, float]
    direction: tuple[float, float]  # unit vector along the wall
    length: float

    @property
    def inward(self) -> tuple[float, float]:
        return self.direction[1], -self.direction[0]  # right of the running direction


def line_walls(
    canvas: Canvas,
    walls: list[Wall],
    keep_out: list[Rect],
    names: tuple[str, ...],
    palette: Palette,
    rng: np.random.Generator,
    fill: float = 1.0,
) -> None:
    """Walk each wall placing random pieces with random gaps; `fill` is the chance a free spot is used."""
    placed = list(keep_out)
    for wall in walls:
        cursor = rng.uniform(*GAP)
        while cursor < wall.length:
            name = str(pick(rng, names))
            piece = FURNITURE[name]
            end = cursor + 2 * piece.half_x
            if end > wall.length:
                cursor += 0.3
                continue
            along = cursor + piece.half_x
            (sx, sy), (dx, dy), (nx, ny) = wall.start, wall.direction, wall.inward
            cx = sx + dx * along + nx * (piece.half_y + 0.02)
            cy = sy + dy * along + ny * (piece.half_y + 0.02)
            ex = abs(dx) * piece.half_x + abs(nx) * piece.half_y
            ey = abs(dy) * piece.half_x + abs(ny) * piece.half_y
            rect = Rect(cx - ex, cy - ey, cx + ex, cy + ey)
            if any(rect.overlaps(r) for r in placed) or rng.random() > fill:
                cursor += 0.3
                continue
            # The piece's front (-y in its frame) must face `inward`: yaw maps (0, -1) onto (nx, ny).
            yaw = math.atan2(nx, -ny)
            piece.build(canvas.item(cx, cy, yaw), rng, palette)
            placed.append(rect)
            cursor = end + rng.uniform(*GAP)

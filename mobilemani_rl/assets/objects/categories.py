"""Per-category scene parameters (docs/reference.md, "Per-category constants") and the skills each kind of
object supports."""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum


class ObjectKind(StrEnum):
    ARTICULATED = "articulated"  # fixed base, one operated joint (open / close)
    CART = "cart"  # free-moving, pushed or pulled by its handle (pull / push)
    RIGID = "rigid"  # free rigid body (pick)


class Place(StrEnum):
    TABLETOP = "tabletop"
    WALL = "wall"
    DOOR = "door"
    OUTDOOR = "outdoor"
    SPACE = "space"


SKILLS_BY_KIND: dict[ObjectKind, tuple[str, ...]] = {
    ObjectKind.ARTICULATED: ("open", "close"),
    ObjectKind.CART: ("pull", "push"),
    ObjectKind.RIGID: ("pick",),
}
ALL_SKILLS = ("open", "close", "pull", "push", "pick")


@dataclass(frozen=True)
class CategoryParams:
    """One row of the reference's per-category table. Scale multiplies the generated geometry;
    mass is the operated link's mass."""

    scale: float
    mass: float
    place: Place
    gravity: bool
    init_joint: float  # radians the operated joint starts past its lower limit
    init_height: float  # metres added under the object (stage top)
    random_height: bool  # stage height randomised U(0, 0.5) m in RL training


def _row(
    scale: float, mass: float, place: Place, gravity: bool, init_deg: float, height: float
) -> CategoryParams:
    random_height = place is Place.TABLETOP
    return CategoryParams(scale, mass, place, gravity, math.radians(init_deg), height, random_height)


CATEGORY_PARAMS: dict[str, CategoryParams] = {
    "holistic": _row(1.0, 0.01, Place.TABLETOP, True, 0, 0.2),
    "box": _row(0.4, 1.0, Place.TABLETOP, False, 10, 0.2),
    "cart": _row(0.5, 0.2, Place.SPACE, True, 0, 0.0),
    "dishwasher": _row(0.4, 1.0, Place.TABLETOP, False, 0, 0.2),
    "faucet": _row(0.2, 1.0, Place.TABLETOP, False, 0, 0.2),
    "laptop": _row(0.4, 1.0, Place.TABLETOP, False, 10, 0.2),
    "microwave": _row(0.5, 1.0, Place.TABLETOP, False, 0, 0.2),
    "oven": _row(0.5, 1.0, Place.TABLETOP, False, 0, 0.2),
    "refrigerator": _row(0.8, 1.0, Place.WALL, False, 0, 0.0),
    "table": _row(0.8, 1.0, Place.WALL, False, 0, 0.0),
    "toilet": _row(0.5, 1.0, Place.WALL, False, 10, 0.0),
    "trashcan": _row(0.4, 1.0, Place.WALL, False, 10, 0.0),
    "washing_machine": _row(0.6, 1.0, Place.WALL, False, 10, 0.0),
    "cabinet": _row(0.8, 1.0, Place.WALL, False, 0, 0.0),
    "car": _row(0.8, 1.0, Place.OUTDOOR, False, 0, 0.0),
    "fridge": _row(1.0, 1.0, Place.WALL, False, 0, 0.0),
    "lever_door": _row(0.8, 1.0, Place.DOOR, False, 0, 0.0),
    "round_door": _row(0.8, 1.0, Place.DOOR, False, 0, 0.0),
    # Windows get a random height too, as in the reference, though they stand in a door-like frame.
    "window": CategoryParams(0.6, 1.0, Place.DOOR, False, 0.0, 0.2, True),
    "safe": _row(1.0, 1.0, Place.TABLETOP, False, 0, 0.2),
}

"""YCB-like rigid objects: fruit, bottles, cans, boxes, tools and toys.

Every shape is at most ~6.5 cm across horizontally (the fingers open 8 cm, and the object spawns at any yaw),
at least ~4.5 cm tall (finger pads are 3.6 cm wide and must clear the stage), with a flat or oblate bottom so
it rests without rolling. The grasp point is the centre of mass; the object weighs 0.01 kg, as in the
reference.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.categories import CATEGORY_PARAMS
from mobilemani_rl.assets.objects.generators.common import (
    BOX,
    CAPSULE,
    CYLINDER,
    ELLIPSOID,
    SPHERE,
    Design,
    choice,
    colour,
    set_body_mass,
    uniform,
)
from mobilemani_rl.assets.objects.parts import (
    add_grasp_site,
    add_part,
    apply_gravity_setting,
    new_object_spec,
)

Body = mujoco.MjsBody
Shape = Callable[[Body], None]
FRUIT = {
    "apple": (0.75, 0.12, 0.1, 1),
    "orange": (0.95, 0.55, 0.1, 1),
    "lemon": (0.95, 0.85, 0.2, 1),
    "pear": (0.7, 0.8, 0.25, 1),
    "plum": (0.4, 0.1, 0.35, 1),
    "peach": (0.95, 0.6, 0.45, 1),
}
STEM = (0.35, 0.22, 0.1, 1)


def _fruit(rng: np.random.Generator) -> Shape:
    kind = choice(rng, tuple(FRUIT))
    rgba = FRUIT[kind]
    r = uniform(rng, 0.026, 0.032)
    flat = uniform(rng, 0.8, 0.9)  # oblate: rests on its flat pole
    along = uniform(rng, 1.0, 1.15) if kind == "lemon" else 1.0

    def shape(body: Body) -> None:
        rz = r * flat
        if kind == "pear":
            add_part(body, ELLIPSOID, (r, r, rz), rgba, pos=(0, 0, rz))
            add_part(body, ELLIPSOID, (0.65 * r, 0.65 * r, 0.9 * r), rgba, pos=(0, 0, 1.6 * rz))
            top = 1.6 * rz + 0.9 * r
        else:
            add_part(body, ELLIPSOID, (r * along, r, rz), rgba, pos=(0, 0, rz))
            top = 2 * rz
        add_part(body, CYLINDER, (0.002, 0.006), STEM, pos=(0, 0, top + 0.004))

    return shape


def _bottle(rng: np.random.Generator) -> Shape:
    r, h = uniform(rng, 0.024, 0.032), uniform(rng, 0.09, 0.15)
    neck_r, neck_h = uniform(rng, 0.35, 0.55) * r, uniform(rng, 0.02, 0.04)
    body_rgba, cap_rgba = colour(rng, choice(rng, ("plastic", "glass"))), colour(rng, "plastic")
    body_rgba = body_rgba[:3] + (1.0,)
    label = rng.random() < 0.6
    label_rgba = colour(rng, "plastic")

    def shape(body: Body) -> None:
        add_part(body, CYLINDER, (r, h / 2), body_rgba, pos=(0, 0, h / 2))
        if label:
            add_part(body, CYLINDER, (r + 0.0008, 0.3 * h), label_rgba, pos=(0, 0, 0.45 * h))
        add_part(body, CAPSULE, (0.75 * r,), body_rgba, fromto=(0, 0, h, 0, 0, h + 0.2 * r))
        add_part(body, CYLINDER, (neck_r, neck_h / 2), body_rgba, pos=(0, 0, h + 0.5 * r + neck_h / 2))
        add_part(body, CYLINDER, (neck_r * 1.15, 0.008), cap_rgba, pos=(0, 0, h + 0.5 * r + neck_h + 0.006))

    return shape


def _can(rng: np.random.Generator) -> Shape:
    r, h = uniform(rng, 0.025, 0.034), uniform(rng, 0.06, 0.13)
    rgba, rim = colour(rng, "plastic"), colour(rng, "metal")

    def shape(body: Body) -> None:
        add_part(body, CYLINDER, (r * 0.96, 0.004), rim, pos=(0, 0, 0.004))
        add_part(body, CYLINDER, (r, h / 2 - 0.008), rgba, pos=(0, 0, h / 2))
        add_part(body, CYLINDER, (r * 0.96, 0.004), rim, pos=(0, 0, h - 0.004))

    return shape


def _box(rng: np.random.Generator) -> Shape:
    sx, sy, sz = uniform(rng, 0.035, 0.06), uniform(rng, 0.03, 0.06), uniform(rng, 0.05, 0.15)
    rgba, band = colour(rng, "plastic"), colour(rng, "plastic")

    def shape(body: Body) -> None:
        add_part(body, BOX, (sx / 2, sy / 2, sz / 2), rgba, pos=(0, 0, sz / 2))
        add_part(body, BOX, (sx / 2 + 0.0008, sy / 2 + 0.0008, 0.15 * sz), band, pos=(0, 0, 0.6 * sz))

    return shape


def _tool(rng: np.random.Generator) -> Shape:
    """Spray bottle, padlock or tape measure."""
    kind = choice(rng, ("spray", "padlock", "tape"))
    a, b, c = uniform(rng, 0.03, 0.045), uniform(rng, 0.025, 0.04), uniform(rng, 0.05, 0.09)
    rgba, metal = colour(rng, "plastic"), colour(rng, "metal")

    def shape(body: Body) -> None:
        if kind == "spray":
            add_part(body, BOX, (a / 2, b / 2, c), rgba, pos=(0, 0, c))
            add_part(body, BOX, (0.01, 0.015, 0.012), metal, pos=(0, -0.005, 2 * c + 0.012))
            add_part(body, CYLINDER, (0.004, 0.01), metal, pos=(0, -0.025, 2 * c + 0.018)).quat = [
                math.sqrt(0.5),
                math.sqrt(0.5),
                0,
                0,
            ]
        elif kind == "padlock":
            add_part(body, BOX, (a / 2, 0.012, c / 2), metal, pos=(0, 0, c / 2))
            x = a / 2 - 0.008
            for sx in (-1, 1):
                add_part(body, CAPSULE, (0.004,), metal, fromto=(sx * x, 0, c, sx * x, 0, c + 0.02))
            add_part(body, CAPSULE, (0.004,), metal, fromto=(-x, 0, c + 0.02, x, 0, c + 0.02))
        else:
            add_part(body, BOX, (0.018, a / 2, a / 2 + 0.01), rgba, pos=(0, 0, a / 2 + 0.01))
            add_part(body, BOX, (0.019, 0.008, 0.006), metal, pos=(0, -a / 2 + 0.008, 0.006))

    return shape


def _toy(rng: np.random.Generator) -> Shape:
    """Stacking block, rubber duck, toy car or peg tower."""
    kind = choice(rng, ("block", "duck", "car", "tower"))
    s = uniform(rng, 0.045, 0.055)
    rgba, accent = colour(rng, "plastic"), colour(rng, "plastic")
    rings = [colour(rng, "plastic") for _ in range(3)]

    def shape(body: Body) -> None:
        if kind == "block":
            add_part(body, BOX, (s / 2, s / 2, s / 2), rgba, pos=(0, 0, s / 2))
        elif kind == "duck":
            add_part(
                body, ELLIPSOID, (0.6 * s, 0.5 * s, 0.35 * s), (0.98, 0.85, 0.1, 1), pos=(0, 0, 0.35 * s)
            )
            add_part(body, SPHERE, (0.28 * s,), (0.98, 0.85, 0.1, 1), pos=(0.25 * s, 0, 0.85 * s))
            add_part(
                body,
                ELLIPSOID,
                (0.15 * s, 0.08 * s, 0.05 * s),
                (0.95, 0.45, 0.1, 1),
                pos=(0.55 * s, 0, 0.82 * s),
            )
        elif kind == "car":
            add_part(body, BOX, (0.6 * s, 0.35 * s, 0.22 * s), rgba, pos=(0, 0, 0.4 * s))
            add_part(body, BOX, (0.35 * s, 0.32 * s, 0.18 * s), accent, pos=(-0.05 * s, 0, 0.8 * s))
            for sx in (-1, 1):
                for sy in (-1, 1):
                    add_part(
                        body,
                        CYLINDER,
                        (0.18 * s, 0.04 * s),
                        (0.1, 0.1, 0.1, 1),
                        pos=(sx * 0.38 * s, sy * 0.3 * s, 0.18 * s),
                    ).quat = [math.sqrt(0.5), math.sqrt(0.5), 0, 0]
        else:
            add_part(body, CYLINDER, (0.5 * s, 0.006), rgba, pos=(0, 0, 0.006))
            add_part(body, CYLINDER, (0.1 * s, 0.6 * s), accent, pos=(0, 0, 0.012 + 0.6 * s))
            for k, (ring, ring_rgba) in enumerate(zip((0.45, 0.38, 0.3), rings, strict=True)):
                add_part(
                    body, CYLINDER, (ring * s, 0.1 * s), ring_rgba, pos=(0, 0, 0.012 + (0.2 * k + 0.1) * s)
                )

    return shape


FAMILIES: dict[str, Callable[[np.random.Generator], Shape]] = {
    "fruit": _fruit,
    "bottle": _bottle,
    "can": _can,
    "box": _box,
    "tool": _tool,
    "toy": _toy,
}


def holistic(rng: np.random.Generator) -> Design:
    family = choice(rng, tuple(FAMILIES))
    shape = FAMILIES[family](rng)

    def build() -> mujoco.MjSpec:
        params = CATEGORY_PARAMS["holistic"]
        spec, root = new_object_spec(f"holistic_{family}")
        shape(root)
        add_grasp_site(root, set_body_mass(root, params.mass))
        apply_gravity_setting(spec, params)
        return spec

    return Design(build, "object", None)

"""Push carts: a deck on four wheels, a push bar facing the robot, and a basket or a second shelf.

The wheels are real hinged cylinders rather than the reference's trick of zeroing friction for carts:
the cart rolls along y when pulled or pushed, resists sliding sideways, and stays put when nothing touches it.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.categories import CATEGORY_PARAMS
from mobilemani_rl.assets.objects.generators.common import (
    BOX,
    CAPSULE,
    CYLINDER,
    HINGE,
    Design,
    add_part,
    add_shell,
    choice,
    colour,
    set_body_mass,
    uniform,
)
from mobilemani_rl.assets.objects.parts import add_grasp_site, apply_gravity_setting, new_object_spec

WHEEL_MASS = 0.005
WHEEL_DAMPING = 0.0005  # bearing drag: negligible when pushed, settles any roll when released
X_AXIS = [math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0]  # turns a cylinder's axis onto x


def cart(rng: np.random.Generator) -> Design:
    w, length, deck_t = uniform(rng, 0.4, 0.6), uniform(rng, 0.6, 0.9), uniform(rng, 0.02, 0.03)
    wheel_r, wheel_w = uniform(rng, 0.05, 0.08), uniform(rng, 0.025, 0.04)
    clearance, bar_h, bar_r = uniform(rng, 0.03, 0.08), uniform(rng, 0.8, 0.95), uniform(rng, 0.012, 0.016)
    extra = choice(rng, ("basket", "shelf", "none"))
    frame_rgba, deck_rgba = colour(rng, "metal"), colour(rng, choice(rng, ("plastic", "wood")))
    grip_rgba = colour(rng, "plastic")
    basket_h = uniform(rng, 0.2, 0.35)

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("cart")
        deck_z = 2 * wheel_r + clearance
        add_part(root, BOX, (w / 2, length / 2, deck_t / 2), deck_rgba, pos=(0, 0, deck_z + deck_t / 2))
        back = -length / 2 + 0.02
        for sx in (-1, 1):
            x = sx * (w / 2 - 0.03)
            add_part(root, CAPSULE, (0.012,), frame_rgba, fromto=(x, back, deck_z, x, back - 0.05, bar_h))
        add_part(
            root,
            CAPSULE,
            (bar_r,),
            grip_rgba,
            fromto=(-(w / 2 - 0.03), back - 0.05, bar_h, w / 2 - 0.03, back - 0.05, bar_h),
        )
        top = deck_z + deck_t
        if extra == "basket":
            add_shell(
                root, (w - 0.02, length - 0.1, basket_h), 0.008, frame_rgba, open_side="top", z0=top, y0=0.04
            )
        elif extra == "shelf":
            for sx in (-1, 1):
                for sy in (-1, 1):
                    x, y = sx * (w / 2 - 0.02), sy * (length / 2 - 0.03)
                    add_part(root, CYLINDER, (0.01, 0.15), frame_rgba, pos=(x, y, top + 0.15))
            add_part(
                root, BOX, (w / 2, length / 2, deck_t / 2), deck_rgba, pos=(0, 0, top + 0.3 + deck_t / 2)
            )
        params = CATEGORY_PARAMS["cart"]
        set_body_mass(root, params.mass - 4 * WHEEL_MASS)
        for sx in (-1, 1):
            for sy in (-1, 1):
                wheel = root.add_body(
                    name=f"wheel_{'lr'[sx > 0]}{'bf'[sy > 0]}",
                    pos=[sx * (w / 2 - wheel_w / 2 - 0.01), sy * (length / 2 - wheel_r - 0.02), wheel_r],
                )
                wheel.add_joint(name=wheel.name + "_axle", type=HINGE, axis=[1, 0, 0], damping=WHEEL_DAMPING)
                add_part(
                    wheel, CYLINDER, (wheel_r, wheel_w / 2), (0.1, 0.1, 0.1, 1), mass=WHEEL_MASS
                ).quat = X_AXIS
        add_grasp_site(root, (0.0, back - 0.05, bar_h))
        apply_gravity_setting(spec, params)
        return spec

    return Design(build, "object", None)

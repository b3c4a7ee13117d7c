"""Single-lever mixer taps: base, column, spout, and a lever that lifts (hinge along x) or swivels (along z).

The grasp point is near the lever's tip, which points toward the robot (the reference fixes the faucet
handle direction instead of measuring it). The spout is turned aside so that it does not sit under the lever's
tip.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.generators.common import (
    CAPSULE,
    CYLINDER,
    GAP,
    HINGE,
    SPHERE,
    Design,
    add_part,
    colour,
    finish,
    hinge_range,
    uniform,
)
from mobilemani_rl.assets.objects.parts import add_moving_link, new_object_spec

TIP_GRIP = 0.012


def faucet(rng: np.random.Generator) -> Design:
    base_r, col_r, col_h = uniform(rng, 0.03, 0.045), uniform(rng, 0.018, 0.026), uniform(rng, 0.15, 0.24)
    spout_z, spout_len, spout_r = (
        uniform(rng, 0.35, 0.5) * col_h,
        uniform(rng, 0.1, 0.16),
        uniform(rng, 0.009, 0.013),
    )
    spout_yaw = math.radians(uniform(rng, 30, 55)) * (1 if rng.random() < 0.5 else -1)
    lever_len, lever_r, ball_r = (
        uniform(rng, 0.08, 0.12),
        uniform(rng, 0.006, 0.009),
        uniform(rng, 0.011, 0.014),
    )
    lift = rng.random() < 0.6
    limits = hinge_range(rng, 65, 90) if lift else hinge_range(rng, 70, 110)
    swivel_sign = 1.0 if rng.random() < 0.5 else -1.0
    chrome, lever_rgba = colour(rng, "metal", 0.03), colour(rng, "metal", 0.03)

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("faucet")
        add_part(root, CYLINDER, (base_r, 0.006), chrome, pos=(0, 0, 0.006))
        add_part(root, CYLINDER, (col_r, col_h / 2), chrome, pos=(0, 0, col_h / 2))
        direction = np.array([math.sin(spout_yaw), -math.cos(spout_yaw), 0.0])
        start = np.array([0.0, 0.0, spout_z]) + col_r * 0.5 * direction
        end = start + spout_len * direction
        add_part(root, CAPSULE, (spout_r,), chrome, fromto=(*start, *end))
        add_part(root, CAPSULE, (spout_r * 0.9,), chrome, fromto=(*end, *(end - (0, 0, 0.03))))
        pivot_z = col_h + ball_r + GAP
        axis = (-1, 0, 0) if lift else (0, 0, swivel_sign)
        lever = add_moving_link(
            root, "lever", (0, 0, pivot_z), joint="lever_hinge", joint_type=HINGE, axis=axis, limits=limits
        )
        add_part(lever, SPHERE, (ball_r,), lever_rgba)
        add_part(lever, CAPSULE, (lever_r,), lever_rgba, fromto=(0, 0, 0, 0, -lever_len, 0))
        grasp = (0.0, -lever_len + TIP_GRIP, 0.0)
        return finish(spec, "faucet", lever, grasp)

    return Design(build, "lever", "lever_hinge")

"""Furniture: cabinets (one or two hinged doors) and tables/desks with a drawer under the top."""

from __future__ import annotations

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.generators.common import (
    BOX,
    CYLINDER,
    GAP,
    Design,
    add_drawer,
    add_part,
    add_shell,
    add_side_hinged_door,
    choice,
    colour,
    finish,
    hinge_range,
    sample_handle,
    uniform,
)
from mobilemani_rl.assets.objects.parts import new_object_spec


def cabinet(rng: np.random.Generator) -> Design:
    """Sideboard, base cabinet or cupboard on a recessed plinth; the robot opens one of its doors."""
    w, d, h = uniform(rng, 0.4, 0.9), uniform(rng, 0.35, 0.55), uniform(rng, 0.6, 1.05)
    plinth, door_t, wall = uniform(rng, 0.05, 0.1), uniform(rng, 0.018, 0.025), 0.018
    family = choice(rng, ("wood", "paint"))
    body_rgba, door_rgba = colour(rng, family), colour(rng, family)
    double = w > 0.55
    hinge_left = rng.random() < 0.5
    limits = hinge_range(rng, 95, 120)
    handle = sample_handle(rng, ("bar", "knob"), length=(0.08, 0.16))
    handle_z = min(h - 0.09, uniform(rng, 0.75, 1.0))

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("cabinet")
        add_shell(root, (w, d, h - plinth), wall, body_rgba, z0=plinth)
        add_part(root, BOX, (w / 2 - 0.03, d / 2 - 0.05, plinth / 2), body_rgba, pos=(0, 0.03, plinth / 2))
        add_part(root, BOX, (w / 2 + 0.01, d / 2 + 0.01, 0.01), door_rgba, pos=(0, 0, h + 0.01))
        front_y = -d / 2 - GAP - door_t
        z_range = (plinth + GAP, h - GAP)
        door_w = w / 2 - GAP if double else w
        hinge_x = -w / 2 if hinge_left else w / 2
        door, s = add_side_hinged_door(
            root,
            "door",
            hinge_x=hinge_x,
            width=door_w,
            z_range=z_range,
            front_y=front_y,
            thickness=door_t,
            limits=limits,
            rgba=door_rgba,
        )
        inset = 0.05 + (handle.length / 2 if handle.kind == "bar" else 0.0)
        grasp = (s * (door_w - inset), -handle.standoff, handle_z)
        handle.add(door, grasp)
        if double:
            # The second door stays shut: part of the carcass, with a matching handle.
            cx = s * (GAP + door_w / 2)
            add_part(
                root,
                BOX,
                (door_w / 2, door_t / 2, (z_range[1] - z_range[0]) / 2),
                door_rgba,
                pos=(cx, front_y + door_t / 2, sum(z_range) / 2),
            )
            handle.add(root, (s * (GAP + inset), front_y - handle.standoff, handle_z))
        return finish(spec, "cabinet", door, grasp)

    return Design(build, "door", "door_hinge")


def table(rng: np.random.Generator) -> Design:
    """Desk or dining table on four legs with a drawer in the apron under the top."""
    w, d, h = uniform(rng, 0.8, 1.4), uniform(rng, 0.5, 0.75), uniform(rng, 0.7, 0.78)
    top_t, leg, wall = uniform(rng, 0.025, 0.04), uniform(rng, 0.04, 0.06), 0.012
    round_legs, shelf = rng.random() < 0.4, rng.random() < 0.3
    dw, dh = uniform(rng, 0.35, min(0.6, w - 2 * leg - 0.1)), uniform(rng, 0.1, 0.14)
    x_off = uniform(rng, -1, 1) * (w / 2 - leg - 0.03 - dw / 2 - wall)
    family = choice(rng, ("wood", "paint"))
    top_rgba, frame_rgba, front_rgba = colour(rng, family), colour(rng, family), colour(rng, family)
    handle = sample_handle(rng, ("bar", "knob"), length=(0.08, 0.16), standoff=(0.035, 0.05))
    travel = uniform(rng, 0.6, 0.8) * (d - 0.16)

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("table")
        add_part(root, BOX, (w / 2, d / 2, top_t / 2), top_rgba, pos=(0, 0, h - top_t / 2))
        leg_h = h - top_t
        for sx in (-1, 1):
            for sy in (-1, 1):
                pos = (sx * (w / 2 - leg / 2 - 0.01), sy * (d / 2 - leg / 2 - 0.01), leg_h / 2)
                if round_legs:
                    add_part(root, CYLINDER, (leg / 2, leg_h / 2), frame_rgba, pos=pos)
                else:
                    add_part(root, BOX, (leg / 2, leg / 2, leg_h / 2), frame_rgba, pos=pos)
        if shelf:
            add_part(root, BOX, (w / 2 - leg - 0.01, d / 2 - leg - 0.01, 0.01), frame_rgba, pos=(0, 0, 0.15))
        # Drawer housing under the top; apron boards close the rest of the front.
        apron_front, housing_d = -d / 2 + 0.025, d - 0.12
        housing_h = dh + 2 * wall
        z0 = leg_h - housing_h
        add_shell(
            root,
            (dw + 2 * wall, housing_d, housing_h),
            wall,
            frame_rgba,
            z0=z0,
            y0=apron_front + housing_d / 2,
            x0=x_off,
        )
        inner = w / 2 - leg - 0.01
        for side in (-1, 1):
            edge = x_off + side * (dw / 2 + wall)
            span = inner - side * edge
            if span > 0.01:
                add_part(
                    root,
                    BOX,
                    (span / 2, wall / 2, housing_h / 2),
                    frame_rgba,
                    pos=(edge + side * span / 2, apron_front + wall / 2, z0 + housing_h / 2),
                )
        front = (dw + 0.016, dh + 0.016, 0.02)
        drawer = add_drawer(
            root,
            "drawer",
            opening=(dw, dh),
            opening_center=(x_off, z0 + housing_h / 2),
            front_y=apron_front,
            depth=housing_d - 0.04,
            travel=travel,
            front_size=front,
            rgba=front_rgba,
            body_rgba=frame_rgba,
        )
        grasp = (0.0, -front[2] - handle.standoff, 0.0)
        handle.add(drawer, grasp)
        return finish(spec, "table", drawer, grasp)

    return Design(build, "drawer", "drawer_slide")

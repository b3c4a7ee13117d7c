"""Doors in frames (UniDoor-like): room doors with a lever or a round knob, casement windows, car doors.

Leaves sit inside their frame opening and hinge on their front edge, so they swing toward the robot (-y)
without touching the jambs.
"""

from __future__ import annotations

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.generators.common import (
    BOX,
    CYLINDER,
    GAP,
    PALETTES,
    Design,
    Handle,
    Rgba,
    add_part,
    add_side_hinged_door,
    colour,
    finish,
    hinge_range,
    sample_handle,
    uniform,
)
from mobilemani_rl.assets.objects.parts import new_object_spec

GLASS: Rgba = PALETTES["glass"][0]


def _frame(
    root: mujoco.MjsBody,
    opening_w: float,
    opening_h: float,
    z0: float,
    bar: float,
    depth: float,
    front_y: float,
    rgba: Rgba,
    *,
    sill: bool,
) -> None:
    """Jambs and head (and a sill) around an opening of (opening_w, opening_h) starting at height z0."""
    y = front_y + depth / 2
    top = z0 + opening_h
    for sx in (-1, 1):
        add_part(
            root,
            BOX,
            (bar / 2, depth / 2, (top + bar) / 2),
            rgba,
            pos=(sx * (opening_w / 2 + bar / 2), y, (top + bar) / 2),
        )
    add_part(root, BOX, (opening_w / 2 + bar, depth / 2, bar / 2), rgba, pos=(0, y, top + bar / 2))
    if sill:
        add_part(root, BOX, (opening_w / 2 + bar, depth / 2, z0 / 2), rgba, pos=(0, y, z0 / 2))


def _room_door(rng: np.random.Generator, category: str, kinds: tuple[str, ...]) -> Design:
    leaf_w, leaf_h, leaf_t = uniform(rng, 0.72, 0.9), uniform(rng, 1.8, 2.05), uniform(rng, 0.035, 0.045)
    bar, depth = uniform(rng, 0.05, 0.08), uniform(rng, 0.1, 0.14)
    frame_rgba, leaf_rgba = colour(rng, "paint"), colour(rng, "wood" if rng.random() < 0.5 else "paint")
    panel_rgba = tuple(0.9 * c for c in leaf_rgba[:3]) + (1.0,)
    hinge_left = rng.random() < 0.5
    limits = hinge_range(rng, 95, 120)
    handle: Handle = sample_handle(rng, kinds, standoff=(0.05, 0.065))
    handle_z, rose_inset = uniform(rng, 0.88, 1.02), uniform(rng, 0.06, 0.075)
    n_panels = int(rng.integers(0, 4))

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec(category)
        front_y, bottom = -depth / 2, 0.01
        _frame(
            root, leaf_w + 2 * GAP, leaf_h + bottom + GAP, 0.0, bar, depth, front_y, frame_rgba, sill=False
        )
        door, s = add_side_hinged_door(
            root,
            "door",
            hinge_x=-leaf_w / 2 if hinge_left else leaf_w / 2,
            width=leaf_w,
            z_range=(bottom, bottom + leaf_h),
            front_y=front_y,
            thickness=leaf_t,
            limits=limits,
            rgba=leaf_rgba,
        )
        for k in range(n_panels):
            zc = bottom + leaf_h * (k + 0.5) / n_panels
            add_part(
                door,
                BOX,
                (0.35 * leaf_w, 0.002, 0.4 * leaf_h / n_panels),
                panel_rgba,
                pos=(s * leaf_w / 2, -0.002, zc),
            )
        rose_u = leaf_w - rose_inset
        grasp_u = rose_u - handle.length / 2 if handle.kind == "lever" else rose_u
        grasp = (s * grasp_u, -handle.standoff, handle_z)
        handle.add(door, grasp, pivot_side=s)
        return finish(spec, category, door, grasp)

    return Design(build, "door", "door_hinge")


def lever_door(rng: np.random.Generator) -> Design:
    return _room_door(rng, "lever_door", ("lever",))


def round_door(rng: np.random.Generator) -> Design:
    return _room_door(rng, "round_door", ("knob",))


def window(rng: np.random.Generator) -> Design:
    """Casement window: frame with sill, glazed sash hinged on one side, lever handle on the other stile."""
    open_w, open_h = uniform(rng, 0.45, 0.7), uniform(rng, 0.45, 0.7)
    bar, depth, sill = uniform(rng, 0.04, 0.06), uniform(rng, 0.06, 0.1), uniform(rng, 0.04, 0.07)
    stile, sash_t = uniform(rng, 0.035, 0.05), uniform(rng, 0.035, 0.05)
    frame_rgba = colour(rng, "paint" if rng.random() < 0.6 else "wood")
    sash_rgba = colour(rng, "paint" if rng.random() < 0.6 else "wood")
    glass = colour(rng, "glass")
    hinge_left = rng.random() < 0.5
    limits = hinge_range(rng, 90, 120)
    handle = sample_handle(rng, ("lever",), length=(0.08, 0.11), standoff=(0.045, 0.06))

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("window")
        front_y = -depth / 2
        _frame(root, open_w, open_h, sill, bar, depth, front_y, frame_rgba, sill=True)
        sash_w, sash_h = open_w - 2 * GAP, open_h - 2 * GAP
        z0 = sill + GAP
        sash, s = add_side_hinged_door(
            root,
            "sash",
            hinge_x=-sash_w / 2 if hinge_left else sash_w / 2,
            width=stile,
            z_range=(z0, z0 + sash_h),
            front_y=front_y,
            thickness=sash_t,
            limits=limits,
            rgba=sash_rgba,
        )
        y = sash_t / 2
        add_part(
            sash,
            BOX,
            (stile / 2, sash_t / 2, sash_h / 2),
            sash_rgba,
            pos=(s * (sash_w - stile / 2), y, z0 + sash_h / 2),
        )
        for z in (z0 + stile / 2, z0 + sash_h - stile / 2):
            add_part(sash, BOX, (sash_w / 2, sash_t / 2, stile / 2), sash_rgba, pos=(s * sash_w / 2, y, z))
        add_part(
            sash,
            BOX,
            (sash_w / 2 - stile, 0.003, sash_h / 2 - stile),
            glass,
            pos=(s * sash_w / 2, y, z0 + sash_h / 2),
        )
        grasp = (s * (sash_w - stile / 2 - handle.length / 2), -handle.standoff, z0 + sash_h / 2)
        handle.add(sash, grasp, pivot_side=s)
        return finish(spec, "window", sash, grasp)

    return Design(build, "sash", "sash_hinge")


def car(rng: np.random.Generator) -> Design:
    """The side of a car: body, cabin, wheels, and the front door hinged at its leading edge."""
    length, depth = uniform(rng, 1.5, 1.9), uniform(rng, 0.5, 0.7)
    sill, belt, roof = uniform(rng, 0.3, 0.38), uniform(rng, 0.85, 0.98), uniform(rng, 1.3, 1.45)
    door_w, door_t, wheel_r = uniform(rng, 0.85, 1.0), uniform(rng, 0.06, 0.09), uniform(rng, 0.28, 0.33)
    paint = colour(rng, "car", 0.03)
    front_left = rng.random() < 0.5  # the car's nose points to -x: the door hinges on its -x edge
    limits = hinge_range(rng, 65, 80)
    handle = sample_handle(rng, ("bar",), length=(0.1, 0.16), standoff=(0.04, 0.05))
    handle_drop = uniform(rng, 0.05, 0.09)

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("car")
        front = -depth / 2
        add_part(root, BOX, (length / 2, depth / 2, (belt - 0.15) / 2), paint, pos=(0, 0, (belt + 0.15) / 2))
        add_part(
            root,
            BOX,
            (0.4 * length, depth / 2 - 0.06, (roof - belt) / 2),
            GLASS,
            pos=(0, 0.03, (roof + belt) / 2),
        )
        add_part(root, BOX, (0.4 * length, depth / 2 - 0.05, 0.02), paint, pos=(0, 0.03, roof))
        for sx in (-1, 1):
            add_part(
                root,
                CYLINDER,
                (wheel_r, 0.1),
                (0.08, 0.08, 0.08, 1),
                pos=(sx * (length / 2 - wheel_r - 0.05), front + 0.11, wheel_r),
            ).quat = [np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0]
        hinge_x = -door_w / 2 if front_left else door_w / 2
        front_y = front - GAP - door_t
        door, s = add_side_hinged_door(
            root,
            "door",
            hinge_x=hinge_x,
            width=door_w,
            z_range=(sill, belt),
            front_y=front_y,
            thickness=door_t,
            limits=limits,
            rgba=paint,
        )
        # Window frame of the door, thinner than its lower panel.
        frame_t, win_h = 0.03, roof - belt - 0.06
        add_part(
            door,
            BOX,
            (0.03, frame_t / 2, win_h / 2),
            paint,
            pos=(s * 0.03, door_t - frame_t / 2, belt + win_h / 2),
        )
        add_part(
            door,
            BOX,
            (door_w / 2, frame_t / 2, 0.02),
            paint,
            pos=(s * door_w / 2, door_t - frame_t / 2, belt + win_h - 0.02),
        )
        add_part(
            door,
            BOX,
            (door_w / 2 - 0.03, 0.003, win_h / 2 - 0.02),
            GLASS,
            pos=(s * door_w / 2, door_t - frame_t / 2, belt + win_h / 2 - 0.01),
        )
        grasp = (s * (door_w - 0.1 - handle.length / 2), -handle.standoff, belt - handle_drop)
        handle.add(door, grasp)
        return finish(spec, "car", door, grasp)

    return Design(build, "door", "door_hinge")

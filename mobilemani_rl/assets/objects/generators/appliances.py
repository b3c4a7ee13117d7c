"""Appliances with a front door or drawer: oven, dishwasher, microwave, washing machine, refrigerator, fridge,
safe. Each is a front-open carcass; the door hangs on its front edge so it swings clear of the carcass.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.generators.common import (
    BOX,
    CYLINDER,
    GAP,
    Design,
    add_bottom_hinged_door,
    add_drawer,
    add_lid,
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

Y_AXIS = [math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0]  # turns a cylinder's axis onto y (knobs, portholes)
GLASS = (0.12, 0.14, 0.16, 1.0)


def _knobs(body: mujoco.MjsBody, xs: np.ndarray, y: float, z: float, radius: float, rgba) -> None:
    for x in xs:
        add_part(body, CYLINDER, (radius, 0.01), rgba, pos=(x, y - 0.01, z)).quat = Y_AXIS


def _drop_door_appliance(
    rng: np.random.Generator, category: str, size: tuple[tuple[float, float], ...], strip: tuple[float, float]
) -> Design:
    """Oven or dishwasher: control strip on top, drop-down door with a bar along its top edge."""
    w, d, h = (uniform(rng, *r) for r in size)
    strip_h, plinth, door_t = uniform(rng, *strip), uniform(rng, 0.02, 0.05), uniform(rng, 0.025, 0.04)
    body_rgba, door_rgba = colour(rng, "appliance"), colour(rng, "appliance")
    limits = hinge_range(rng, 80, 95)
    handle = sample_handle(rng, ("bar",), length=(0.55 * w, 0.85 * w), standoff=(0.045, 0.06))
    n_knobs = int(rng.integers(2, 6))
    window = category == "oven" or rng.random() < 0.2

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec(category)
        add_shell(root, (w, d, h), 0.015, body_rgba)
        front = -d / 2
        add_part(
            root, BOX, (w / 2, 0.01, strip_h / 2), body_rgba, pos=(0, front - 0.01 + 0.0001, h - strip_h / 2)
        )
        knob_y = front - 0.02
        _knobs(root, np.linspace(-0.35 * w, 0.35 * w, n_knobs), knob_y, h - strip_h / 2, 0.4 * strip_h, GLASS)
        height = h - strip_h - plinth - 2 * GAP
        door = add_bottom_hinged_door(
            root,
            "door",
            x_range=(-w / 2, w / 2),
            hinge_z=plinth + GAP,
            height=height,
            front_y=front - GAP - door_t,
            thickness=door_t,
            limits=limits,
            rgba=door_rgba,
        )
        if window:
            add_part(door, BOX, (0.33 * w, 0.001, 0.25 * height), GLASS, pos=(0, -0.001, 0.45 * height))
        grasp = (0.0, -handle.standoff, height - 0.04)
        handle.add(door, grasp)
        return finish(spec, category, door, grasp)

    return Design(build, "door", "door_hinge")


def oven(rng: np.random.Generator) -> Design:
    return _drop_door_appliance(rng, "oven", ((0.45, 0.6), (0.45, 0.55), (0.42, 0.55)), (0.06, 0.1))


def dishwasher(rng: np.random.Generator) -> Design:
    """Drop-down door (most), or a dish drawer that slides out (a quarter of them)."""
    if rng.random() < 0.75:
        return _drop_door_appliance(rng, "dishwasher", ((0.38, 0.48), (0.38, 0.48), (0.4, 0.5)), (0.04, 0.07))
    w, d, h = uniform(rng, 0.38, 0.48), uniform(rng, 0.4, 0.5), uniform(rng, 0.25, 0.35)
    body_rgba, front_rgba = colour(rng, "appliance"), colour(rng, "appliance")
    travel = uniform(rng, 0.55, 0.7) * d
    handle = sample_handle(rng, ("bar",), length=(0.5 * w, 0.8 * w), standoff=(0.04, 0.055))

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("dishwasher")
        add_shell(root, (w, d, h), 0.015, body_rgba)
        front_h = h - 0.02
        drawer = add_drawer(
            root,
            "drawer",
            opening=(w - 0.03, h - 0.03),
            opening_center=(0, h / 2),
            front_y=-d / 2,
            depth=d - 0.06,
            travel=travel,
            front_size=(w, front_h, 0.03),
            rgba=front_rgba,
            body_rgba=(0.6, 0.62, 0.65, 1),
        )
        grasp = (0.0, -0.03 - handle.standoff, front_h / 2 - 0.04)
        handle.add(drawer, grasp)
        return finish(spec, "dishwasher", drawer, grasp)

    return Design(build, "drawer", "drawer_slide")


def microwave(rng: np.random.Generator) -> Design:
    """Door hinged on the left, control panel on the right, short pull bar at the door's free edge."""
    w, d, h = uniform(rng, 0.42, 0.55), uniform(rng, 0.32, 0.42), uniform(rng, 0.26, 0.34)
    panel_w, door_t = uniform(rng, 0.1, 0.14), uniform(rng, 0.02, 0.03)
    body_rgba, door_rgba = colour(rng, "appliance"), colour(rng, "appliance")
    limits = hinge_range(rng, 100, 130)
    handle = sample_handle(rng, ("bar",), length=(0.06, 0.1), standoff=(0.04, 0.055))
    n_buttons = int(rng.integers(3, 7))

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("microwave")
        feet = 0.012
        add_shell(root, (w, d, h - feet), 0.012, body_rgba, z0=feet)
        for sx in (-1, 1):
            for sy in (-1, 1):
                add_part(
                    root,
                    CYLINDER,
                    (0.015, feet / 2),
                    GLASS,
                    pos=(sx * (w / 2 - 0.04), sy * (d / 2 - 0.04), feet / 2),
                )
        front = -d / 2
        panel_x = w / 2 - panel_w / 2
        add_part(
            root, BOX, (panel_w / 2, 0.01, (h - feet) / 2), GLASS, pos=(panel_x, front + 0.01, (h + feet) / 2)
        )
        for z in np.linspace(h - 0.06, feet + 0.06, n_buttons):
            add_part(root, BOX, (0.025, 0.004, 0.008), body_rgba, pos=(panel_x, front - 0.003, z))
        door_w = w - panel_w - GAP
        door, s = add_side_hinged_door(
            root,
            "door",
            hinge_x=-w / 2,
            width=door_w,
            z_range=(feet + GAP, h - GAP),
            front_y=front - GAP - door_t,
            thickness=door_t,
            limits=limits,
            rgba=door_rgba,
        )
        z_mid = (h + feet) / 2
        add_part(door, BOX, (0.36 * door_w, 0.001, 0.3 * h), GLASS, pos=(s * 0.45 * door_w, -0.001, z_mid))
        grasp = (s * (door_w - handle.length / 2 - 0.015), -handle.standoff, z_mid)
        handle.add(door, grasp)
        return finish(spec, "microwave", door, grasp)

    return Design(build, "door", "door_hinge")


def washing_machine(rng: np.random.Generator) -> Design:
    """Front loader (round door on a side hinge, grip at its free edge) or top loader (lid behind a tab)."""
    front_loader = rng.random() < 0.7
    w, d = uniform(rng, 0.5, 0.6), uniform(rng, 0.45, 0.6)
    h = uniform(rng, 0.75, 0.9) if front_loader else uniform(rng, 0.72, 0.82)
    radius, door_t = uniform(rng, 0.15, 0.19), uniform(rng, 0.04, 0.06)
    body_rgba, door_rgba = colour(rng, "appliance"), colour(rng, "appliance")
    limits = hinge_range(rng, 100, 150)
    handle = sample_handle(rng, ("bar",), length=(0.05, 0.08), standoff=(0.035, 0.05))
    panel_h, dial_x = uniform(rng, 0.08, 0.12), uniform(rng, -0.2, 0.2) * w

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("washing_machine")
        front = -d / 2
        if not front_loader:
            add_shell(root, (w, d, h), 0.015, body_rgba, open_side="top")
            # Console along the back; the lid's hinge leaves room for the lid's edge to swing up past it.
            lid_t = 0.02
            add_part(root, BOX, (w / 2, panel_h / 2, 0.06), body_rgba, pos=(0, d / 2 - panel_h / 2, h + 0.06))
            # The dial sits on top of the console: on its face it would be in the opening lid's way.
            add_part(root, CYLINDER, (0.03, 0.01), GLASS, pos=(dial_x, d / 2 - panel_h / 2, h + 0.13))
            hinge_y = d / 2 - panel_h - lid_t - GAP
            depth = hinge_y + d / 2
            lid = add_lid(
                root,
                "lid",
                hinge_y=hinge_y,
                hinge_z=h + GAP,
                width=w - 0.01,
                depth=depth,
                thickness=lid_t,
                limits=limits,
                rgba=door_rgba,
            )
            add_part(lid, BOX, (0.06, 0.02, 0.006), door_rgba, pos=(0, -depth - 0.02, 0.01))
            grasp = (0.0, -depth - 0.04 + 0.012, 0.01)
            return finish(spec, "washing_machine", lid, grasp)
        add_part(root, BOX, (w / 2, d / 2, h / 2), body_rgba, pos=(0, 0, h / 2))
        _knobs(root, [dial_x], front, h - panel_h / 2, 0.03, GLASS)
        cz = 0.06 + radius + 0.5 * (h - panel_h - 0.06 - 2 * radius)
        # A short hinge arm on the left carries the round door.
        door, s = add_side_hinged_door(
            root,
            "door",
            hinge_x=-radius - 0.02,
            width=0.03,
            z_range=(cz - 0.05, cz + 0.05),
            front_y=front - GAP - door_t,
            thickness=door_t,
            limits=limits,
            rgba=door_rgba,
        )
        centre = s * (radius + 0.02)
        add_part(door, CYLINDER, (radius, door_t / 2), door_rgba, pos=(centre, door_t / 2, cz)).quat = Y_AXIS
        add_part(door, CYLINDER, (0.7 * radius, 0.002), GLASS, pos=(centre, -0.001, cz)).quat = Y_AXIS
        grasp = (centre + s * (radius - 0.015), -handle.standoff, cz)
        handle.add(door, grasp)
        return finish(spec, "washing_machine", door, grasp)

    part = "door" if front_loader else "lid"
    return Design(build, part, f"{part}_hinge")


def refrigerator(rng: np.random.Generator) -> Design:
    """Tall fridge: single door, top or bottom freezer, or side by side; the operated door has a vertical bar
    (the reference rewards a turned palm when opening refrigerators)."""
    layout = choice(rng, ("single", "top_freezer", "bottom_freezer", "side_by_side"))
    w, d, h = uniform(rng, 0.55, 0.8), uniform(rng, 0.55, 0.7), uniform(rng, 1.3, 1.75)
    door_t, split = uniform(rng, 0.04, 0.06), uniform(rng, 0.28, 0.36)
    body_rgba = colour(rng, "appliance")
    limits = hinge_range(rng, 100, 130)
    hinge_left = rng.random() < 0.5
    handle = sample_handle(rng, ("bar",), length=(0.25, 0.45), standoff=(0.045, 0.06), vertical=True)
    handle_z = uniform(rng, 0.85, 1.05)
    plinth = uniform(rng, 0.04, 0.08)

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("refrigerator")
        add_shell(root, (w, d, h - plinth), 0.03, body_rgba, z0=plinth)
        add_part(root, BOX, (w / 2 - 0.02, d / 2 - 0.02, plinth / 2), GLASS, pos=(0, 0.02, plinth / 2))
        front_y = -d / 2 - GAP - door_t
        z0, z1 = plinth + GAP, h - GAP
        x0, x1 = -w / 2, w / 2
        fixed: list[tuple[float, float, float, float]] = []  # other doors: x0, x1, z0, z1
        if layout == "top_freezer":
            cut = h - split * (h - plinth)
            fixed.append((x0, x1, cut + GAP, z1))
            z1 = cut - GAP
        elif layout == "bottom_freezer":
            cut = plinth + split * (h - plinth)
            fixed.append((x0, x1, z0, cut - GAP))
            z0 = cut + GAP
        elif layout == "side_by_side":
            fixed.append((0.0 + GAP, x1, z0, z1) if hinge_left else (x0, -GAP, z0, z1))
            x0, x1 = (x0, -GAP) if hinge_left else (GAP, x1)
        for fx0, fx1, fz0, fz1 in fixed:
            add_part(
                root,
                BOX,
                ((fx1 - fx0) / 2, door_t / 2, (fz1 - fz0) / 2),
                body_rgba,
                pos=((fx0 + fx1) / 2, front_y + door_t / 2, (fz0 + fz1) / 2),
            )
        width = x1 - x0
        door, s = add_side_hinged_door(
            root,
            "door",
            hinge_x=x0 if hinge_left else x1,
            width=width,
            z_range=(z0, z1),
            front_y=front_y,
            thickness=door_t,
            limits=limits,
            rgba=body_rgba,
        )
        z = float(np.clip(handle_z, z0 + handle.length / 2 + 0.03, z1 - handle.length / 2 - 0.03))
        grasp = (s * (width - 0.06), -handle.standoff, z)
        handle.add(door, grasp)
        return finish(spec, "refrigerator", door, grasp)

    return Design(build, "door", "door_hinge")


def fridge(rng: np.random.Generator) -> Design:
    """Compact or under-counter fridge / wine cooler; horizontal pull bar along the top of its door."""
    w, d, h = uniform(rng, 0.45, 0.65), uniform(rng, 0.45, 0.6), uniform(rng, 0.8, 1.2)
    door_t = uniform(rng, 0.04, 0.06)
    body_rgba = colour(rng, choice(rng, ("appliance", "plastic")))
    glass_door = rng.random() < 0.35
    limits = hinge_range(rng, 100, 130)
    hinge_left = rng.random() < 0.5
    handle = sample_handle(rng, ("bar",), length=(0.2, 0.35), standoff=(0.045, 0.06))
    n_shelves = int(rng.integers(2, 5))

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("fridge")
        add_shell(root, (w, d, h), 0.03, body_rgba)
        for z in np.linspace(0.2, h - 0.2, n_shelves):
            add_part(root, BOX, (w / 2 - 0.03, d / 2 - 0.04, 0.004), (0.8, 0.85, 0.9, 1), pos=(0, 0.02, z))
        door, s = add_side_hinged_door(
            root,
            "door",
            hinge_x=-w / 2 if hinge_left else w / 2,
            width=w,
            z_range=(GAP, h - GAP),
            front_y=-d / 2 - GAP - door_t,
            thickness=door_t,
            limits=limits,
            rgba=body_rgba,
        )
        if glass_door:
            add_part(door, BOX, (0.38 * w, 0.001, 0.36 * h), GLASS, pos=(s * w / 2, -0.001, 0.45 * h))
        grasp = (s * w / 2, -handle.standoff, h - 0.07)
        handle.add(door, grasp)
        return finish(spec, "fridge", door, grasp)

    return Design(build, "door", "door_hinge")


def safe(rng: np.random.Generator) -> Design:
    """Steel safe: thick walls, heavy door with a combination dial and a lever or bar handle."""
    w, d, h = uniform(rng, 0.32, 0.5), uniform(rng, 0.32, 0.45), uniform(rng, 0.3, 0.5)
    wall, door_t = uniform(rng, 0.03, 0.05), uniform(rng, 0.04, 0.07)
    body_rgba, dial_rgba = colour(rng, choice(rng, ("metal", "appliance", "paint"))), colour(rng, "metal")
    limits = hinge_range(rng, 100, 140)
    hinge_left = rng.random() < 0.5
    handle = sample_handle(rng, ("lever", "bar"), length=(0.09, 0.13), standoff=(0.045, 0.06))

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("safe")
        add_shell(root, (w, d, h), wall, body_rgba)
        door, s = add_side_hinged_door(
            root,
            "door",
            hinge_x=-w / 2 if hinge_left else w / 2,
            width=w,
            z_range=(GAP, h - GAP),
            front_y=-d / 2 - GAP - door_t,
            thickness=door_t,
            limits=limits,
            rgba=body_rgba,
        )
        add_part(door, CYLINDER, (0.035, 0.008), dial_rgba, pos=(s * 0.45 * w, -0.008, 0.7 * h)).quat = Y_AXIS
        grasp = (s * (w - 0.06 - handle.length / 2), -handle.standoff, 0.42 * h)
        handle.add(door, grasp, pivot_side=s)
        return finish(spec, "safe", door, grasp)

    return Design(build, "door", "door_hinge")

"""Objects opened by lifting a lid hinged along its back edge: box, laptop, toilet, trashcan.

The grasp point is the lid's free (front) edge, as the reference refines it (to the points that move most): a
protruding tab or lip the fingers close on from above and below, or a bar handle in front of the edge.
"""

from __future__ import annotations

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.generators.common import (
    BOX,
    CYLINDER,
    ELLIPSOID,
    GAP,
    Design,
    Rgba,
    add_lid,
    add_part,
    add_shell,
    choice,
    colour,
    finish,
    hinge_range,
    sample_handle,
    uniform,
)
from mobilemani_rl.assets.objects.parts import new_object_spec

TAB_GRIP = 0.012  # grasp point this far inside a tab's or lip's tip, so the finger pads cover it


def _tab(rng: np.random.Generator) -> tuple[float, float, float]:
    """Width, protrusion and thickness of a grip tab on a lid's front edge."""
    return uniform(rng, 0.06, 0.12), uniform(rng, 0.035, 0.05), uniform(rng, 0.008, 0.012)


def _add_tab(
    lid: mujoco.MjsBody,
    edge_y: float,
    z: float,
    tab: tuple[float, float, float],
    rgba: Rgba,
) -> tuple[float, float, float]:
    """A tab sticking out of the lid's front edge at height z; returns the grasp point."""
    width, length, thick = tab
    add_part(lid, BOX, (width / 2, length / 2, thick / 2), rgba, pos=(0, edge_y - length / 2, z))
    return 0.0, edge_y - length + TAB_GRIP, z


def box(rng: np.random.Generator) -> Design:
    """Storage chest, shoe box or tool box: open-top shell and a lid with a tab or a bar handle."""
    w, d, h = uniform(rng, 0.25, 0.42), uniform(rng, 0.18, 0.3), uniform(rng, 0.1, 0.22)
    wall, lid_t, overhang = uniform(rng, 0.008, 0.014), uniform(rng, 0.01, 0.02), uniform(rng, 0.0, 0.012)
    family = choice(rng, ("wood", "plastic", "paint"))
    body_rgba, lid_rgba = colour(rng, family), colour(rng, family)
    limits = hinge_range(rng, 100, 135)
    tab = _tab(rng) if rng.random() < 0.5 else None
    handle = sample_handle(rng, ("bar",), length=(0.07, 0.14), standoff=(0.035, 0.05))

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("box")
        add_shell(root, (w, d, h), wall, body_rgba, open_side="top")
        depth = d + overhang
        lid = add_lid(
            root,
            "lid",
            hinge_y=d / 2,
            hinge_z=h + GAP,
            width=w + 2 * overhang,
            depth=depth,
            thickness=lid_t,
            limits=limits,
            rgba=lid_rgba,
        )
        if tab is not None:
            grasp = _add_tab(lid, -depth, lid_t / 2, tab, lid_rgba)
        else:
            grasp = (0.0, -depth - handle.standoff, lid_t / 2)
            handle.add(lid, grasp)
        return finish(spec, "box", lid, grasp)

    return Design(build, "lid", "lid_hinge")


def laptop(rng: np.random.Generator) -> Design:
    """Clamshell laptop: base with keyboard; the screen lid overhangs the base front a little
    (the grip lip)."""
    w, d, t = uniform(rng, 0.28, 0.38), uniform(rng, 0.19, 0.26), uniform(rng, 0.015, 0.025)
    screen_t, lip = uniform(rng, 0.006, 0.01), uniform(rng, 0.03, 0.04)
    shell_rgba = colour(rng, choice(rng, ("metal", "plastic")))
    keys_rgba, display_rgba = colour(rng, "metal", 0.02), (0.05, 0.07, 0.1, 1.0)
    keys_rgba = (keys_rgba[0] * 0.3, keys_rgba[1] * 0.3, keys_rgba[2] * 0.3, 1.0)
    limits = hinge_range(rng, 120, 170)

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("laptop")
        add_part(root, BOX, (w / 2, d / 2, t / 2), shell_rgba, pos=(0, 0, t / 2))
        add_part(root, BOX, (0.42 * w, 0.28 * d, 0.001), keys_rgba, pos=(0, -0.05 * d, t - 0.0005))
        add_part(root, BOX, (0.12 * w, 0.1 * d, 0.001), keys_rgba, pos=(0, -0.38 * d, t - 0.0005))
        depth = d + lip
        screen = add_lid(
            root,
            "screen",
            hinge_y=d / 2,
            hinge_z=t + GAP,
            width=w - 0.004,
            depth=depth,
            thickness=screen_t,
            limits=limits,
            rgba=shell_rgba,
        )
        add_part(screen, BOX, (0.45 * w, 0.4 * depth, 0.0008), display_rgba, pos=(0, -0.5 * depth, 0.0008))
        grasp = (0.0, -depth + 0.008, screen_t / 2)
        return finish(spec, "laptop", screen, grasp)

    return Design(build, "screen", "screen_hinge")


def toilet(rng: np.random.Generator) -> Design:
    """Pedestal, oval bowl rim, seat ring, tank against the wall, and the lid hinged in front of the tank."""
    rx, ry, rz = uniform(rng, 0.17, 0.2), uniform(rng, 0.21, 0.25), uniform(rng, 0.05, 0.07)
    rim_top = uniform(rng, 0.36, 0.42)
    ped_w, seat_t, lid_t, lip = (
        uniform(rng, 0.16, 0.22),
        uniform(rng, 0.012, 0.02),
        uniform(rng, 0.02, 0.03),
        uniform(rng, 0.02, 0.03),
    )
    tank = (uniform(rng, 0.34, 0.44), uniform(rng, 0.13, 0.19), uniform(rng, 0.3, 0.38))
    porcelain, seat_rgba = (
        colour(rng, "ceramic", 0.02),
        colour(rng, choice(rng, ("ceramic", "wood", "plastic"))),
    )
    button_rgba = colour(rng, "metal")
    limits = hinge_range(rng, 92, 100)

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("toilet")
        bowl_z = rim_top - rz
        add_part(root, BOX, (ped_w / 2, 0.7 * ry, bowl_z / 2), porcelain, pos=(0, 0.1 * ry, bowl_z / 2))
        add_part(root, ELLIPSOID, (rx, ry, rz), porcelain, pos=(0, 0, bowl_z))
        # Seat ring: four flat bars on the rim.
        bar = 0.045
        for sx in (-1, 1):
            add_part(
                root,
                BOX,
                (bar / 2, ry * 0.9, seat_t / 2),
                seat_rgba,
                pos=(sx * (rx - bar / 2 - 0.01), 0, rim_top + seat_t / 2),
            )
        for sy in (-1, 1):
            add_part(
                root,
                BOX,
                (rx - 0.01, bar / 2, seat_t / 2),
                seat_rgba,
                pos=(0, sy * (0.9 * ry - bar / 2), rim_top + seat_t / 2),
            )
        hinge_y, hinge_z = ry, rim_top + seat_t + GAP
        tw, td, th = tank
        # The tank stands clear of the hinge by the lid's thickness so the lid can swing past vertical.
        tank_y = hinge_y + lid_t + 0.03 + td / 2
        add_part(root, BOX, (tw / 2, td / 2, th / 2), porcelain, pos=(0, tank_y, rim_top - 0.05 + th / 2))
        add_part(
            root,
            BOX,
            (ped_w / 2, (tank_y - 0.5 * ry) / 2, (rim_top - 0.05) / 2),
            porcelain,
            pos=(0, (tank_y + 0.5 * ry) / 2, (rim_top - 0.05) / 2),
        )
        add_part(root, CYLINDER, (0.018, 0.006), button_rgba, pos=(0, tank_y, rim_top - 0.05 + th + 0.006))
        depth = 2 * ry + lip
        lid = add_lid(
            root,
            "lid",
            hinge_y=hinge_y,
            hinge_z=hinge_z,
            width=2 * rx,
            depth=depth,
            thickness=lid_t,
            limits=limits,
            rgba=seat_rgba,
        )
        grasp = (0.0, -depth + TAB_GRIP, lid_t / 2)
        return finish(spec, "toilet", lid, grasp)

    return Design(build, "lid", "lid_hinge")


def trashcan(rng: np.random.Generator) -> Design:
    """Pedal bin, square or round, whose lid has a grip tab at the front."""
    round_body = rng.random() < 0.5
    w, d, h = uniform(rng, 0.26, 0.4), uniform(rng, 0.24, 0.34), uniform(rng, 0.38, 0.62)
    radius = uniform(rng, 0.12, 0.18)
    lid_t, tab = uniform(rng, 0.015, 0.03), _tab(rng)
    family = choice(rng, ("metal", "plastic"))
    body_rgba, lid_rgba, pedal_rgba = colour(rng, family), colour(rng, family), colour(rng, "metal")
    limits = hinge_range(rng, 90, 120)

    def build() -> mujoco.MjSpec:
        spec, root = new_object_spec("trashcan")
        if round_body:
            add_part(root, CYLINDER, (radius, h / 2), body_rgba, pos=(0, 0, h / 2))
            half_d, lid_w = radius, 2 * radius + 0.01
        else:
            add_shell(root, (w, d, h), 0.01, body_rgba, open_side="top")
            half_d, lid_w = d / 2, w + 0.01
        add_part(root, BOX, (0.05, 0.03, 0.008), pedal_rgba, pos=(0, -half_d - 0.03, 0.02))
        depth = 2 * half_d + 0.01
        lid = add_lid(
            root,
            "lid",
            hinge_y=half_d,
            hinge_z=h + GAP,
            width=lid_w,
            depth=depth,
            thickness=lid_t,
            limits=limits,
            rgba=lid_rgba,
        )
        grasp = _add_tab(lid, -depth, lid_t / 2, tab, lid_rgba)
        return finish(spec, "trashcan", lid, grasp)

    return Design(build, "lid", "lid_hinge")

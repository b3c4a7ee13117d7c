"""Building blocks shared by the category generators: colours, sampled dimensions, carcasses, handles, links.

All generators build in metres at the category's scale (CategoryParams.scale already applied), in the
object frame: front (where the robot stands) toward -y, bottom at z = 0. Moving parts keep a few millimetres
of clearance from the fixed parts so that sweeping a joint never makes the object touch itself.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.categories import CATEGORY_PARAMS
from mobilemani_rl.assets.objects.parts import (
    BOX,
    CAPSULE,
    CYLINDER,
    add_grasp_site,
    add_moving_link,
    add_part,
    apply_gravity_setting,
)

ELLIPSOID = mujoco.mjtGeom.mjGEOM_ELLIPSOID
SPHERE = mujoco.mjtGeom.mjGEOM_SPHERE
HINGE = mujoco.mjtJoint.mjJNT_HINGE
SLIDE = mujoco.mjtJoint.mjJNT_SLIDE
GAP = 0.004  # clearance between a moving part and the fixed body

Vec = Sequence[float]
Rgba = tuple[float, float, float, float]

# Base colours per material family; each object jitters its pick a little so no two look identical.
PALETTES: dict[str, tuple[Rgba, ...]] = {
    "wood": ((0.62, 0.45, 0.30, 1), (0.45, 0.30, 0.18, 1), (0.78, 0.64, 0.46, 1), (0.35, 0.22, 0.14, 1)),
    "appliance": ((0.92, 0.92, 0.90, 1), (0.75, 0.76, 0.78, 1), (0.20, 0.20, 0.22, 1), (0.85, 0.86, 0.88, 1)),
    "plastic": (
        (0.85, 0.2, 0.2, 1),
        (0.2, 0.45, 0.8, 1),
        (0.25, 0.65, 0.3, 1),
        (0.95, 0.75, 0.2, 1),
        (0.55, 0.3, 0.7, 1),
        (0.3, 0.3, 0.32, 1),
        (0.9, 0.9, 0.88, 1),
    ),
    "metal": ((0.55, 0.56, 0.58, 1), (0.30, 0.30, 0.32, 1), (0.72, 0.72, 0.70, 1), (0.62, 0.5, 0.3, 1)),
    "paint": (
        (0.93, 0.92, 0.88, 1),
        (0.55, 0.62, 0.70, 1),
        (0.70, 0.55, 0.45, 1),
        (0.35, 0.45, 0.40, 1),
        (0.80, 0.78, 0.70, 1),
    ),
    "ceramic": ((0.96, 0.96, 0.95, 1), (0.90, 0.90, 0.86, 1), (0.85, 0.88, 0.92, 1)),
    "glass": ((0.45, 0.6, 0.7, 0.55), (0.25, 0.3, 0.35, 0.7), (0.6, 0.75, 0.8, 0.45)),
    "car": (
        (0.7, 0.1, 0.1, 1),
        (0.1, 0.2, 0.5, 1),
        (0.8, 0.8, 0.82, 1),
        (0.12, 0.12, 0.13, 1),
        (0.2, 0.45, 0.3, 1),
        (0.9, 0.6, 0.1, 1),
    ),
}


def colour(rng: np.random.Generator, family: str, jitter: float = 0.05) -> Rgba:
    base = PALETTES[family][int(rng.integers(len(PALETTES[family])))]
    rgb = np.clip(np.asarray(base[:3]) + rng.uniform(-jitter, jitter, 3), 0.0, 1.0)
    return (float(rgb[0]), float(rgb[1]), float(rgb[2]), float(base[3]))


def uniform(rng: np.random.Generator, low: float, high: float) -> float:
    return float(rng.uniform(low, high))


def choice(rng: np.random.Generator, options: Sequence):
    return options[int(rng.integers(len(options)))]


def hinge_range(rng: np.random.Generator, low_deg: float, high_deg: float) -> tuple[float, float]:
    """Closed at 0, upper limit sampled: the operated joint's range."""
    return 0.0, math.radians(uniform(rng, low_deg, high_deg))


def add_shell(
    body: mujoco.MjsBody,
    size: Vec,
    wall: float,
    rgba: Rgba,
    *,
    open_side: str = "front",
    z0: float = 0.0,
    y0: float = 0.0,
    x0: float = 0.0,
) -> None:
    """A hollow box (carcass, tub, bin) centred on x = x0, y = y0, standing on z = z0, one face left open.

    `open_side`: "front" (-y face missing: cabinets, ovens) or "top" (+z face missing: bins, drawers).
    """
    w, d, h = size
    t = wall / 2
    faces = {
        "bottom": ((w / 2, d / 2, t), (0, 0, t)),
        "top": ((w / 2, d / 2, t), (0, 0, h - t)),
        "left": ((t, d / 2, h / 2), (-w / 2 + t, 0, h / 2)),
        "right": ((t, d / 2, h / 2), (w / 2 - t, 0, h / 2)),
        "back": ((w / 2, t, h / 2), (0, d / 2 - t, h / 2)),
        "front": ((w / 2, t, h / 2), (0, -d / 2 + t, h / 2)),
    }
    for face, (half, pos) in faces.items():
        if face != open_side:
            add_part(body, BOX, half, rgba, pos=(pos[0] + x0, pos[1] + y0, pos[2] + z0))


def add_bar_handle(
    link: mujoco.MjsBody,
    center: Vec,
    length: float,
    radius: float,
    standoff: float,
    rgba: Rgba,
    *,
    vertical: bool = False,
) -> None:
    """A bar (along x, or z if vertical) held `standoff` in front (-y) of the surface by two posts.

    `center` is the bar's centre, i.e. the grasp point; the surface is at center.y + standoff.
    """
    cx, cy, cz = center
    half = length / 2
    axis = np.array((0.0, 0.0, 1.0)) if vertical else np.array((1.0, 0.0, 0.0))
    ends = [np.asarray(center) - half * axis, np.asarray(center) + half * axis]
    add_part(link, CAPSULE, (radius,), rgba, fromto=(*ends[0], *ends[1]))
    post = 0.8 * radius
    for end in ends:
        add_part(link, CYLINDER, (post,), rgba, fromto=(end[0], cy, end[2], end[0], cy + standoff, end[2]))


def add_knob(link: mujoco.MjsBody, center: Vec, radius: float, standoff: float, rgba: Rgba) -> None:
    """A round knob (sphere on a stem) whose centre, the grasp point,
    is `standoff` in front of the surface."""
    cx, cy, cz = center
    add_part(link, SPHERE, (radius,), rgba, pos=center)
    add_part(link, CYLINDER, (0.35 * radius,), rgba, fromto=(cx, cy, cz, cx, cy + standoff, cz))
    add_part(
        link,
        CYLINDER,
        (1.2 * radius, 0.004),
        rgba,
        pos=(cx, cy + standoff - 0.004, cz),
    ).quat = _quat_y_axis()


def add_lever(
    link: mujoco.MjsBody, grasp: Vec, length: float, standoff: float, pivot_side: float, rgba: Rgba
) -> None:
    """A lever door handle: rose and stem at one end, horizontal grip along x ending past the grasp point.

    `pivot_side` (+1 or -1) is where the stem sits relative to the grasp point along x.
    """
    gx, gy, gz = grasp
    px = gx + pivot_side * length / 2
    tip = gx - pivot_side * length / 2
    add_part(link, CAPSULE, (0.011,), rgba, fromto=(px, gy, gz, tip, gy, gz))
    add_part(link, CYLINDER, (0.009,), rgba, fromto=(px, gy, gz, px, gy + standoff, gz))
    add_part(link, CYLINDER, (0.028, 0.005), rgba, pos=(px, gy + standoff - 0.005, gz)).quat = _quat_y_axis()


def _quat_y_axis() -> list[float]:
    """Orientation that turns a cylinder's z axis onto y (discs lying flat on a door face)."""
    return [math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0]


def add_side_hinged_door(
    parent: mujoco.MjsBody,
    name: str,
    *,
    hinge_x: float,
    width: float,
    z_range: Vec,
    front_y: float,
    thickness: float,
    limits: tuple[float, float],
    rgba: Rgba,
) -> tuple[mujoco.MjsBody, float]:
    """A door on a vertical hinge at x = hinge_x, front face at y = front_y, swinging toward -y.

    The axis runs along the door's front edge (as real hinge pins on the side a door swings into), so every
    point of the leaf moves forward and toward its own side: it clears a carcass behind it or jambs beside it.
    The leaf extends from the hinge toward the other side. Returns the link (frame on the axis, z = 0 of the
    parent; the leaf occupies y in [0, thickness]) and the sign s (+1: the leaf extends toward +x).
    """
    s = 1.0 if hinge_x < 0 else -1.0
    link = add_moving_link(
        parent,
        name,
        (hinge_x, front_y, 0.0),
        joint=f"{name}_hinge",
        joint_type=HINGE,
        axis=(0, 0, -s),
        limits=limits,
    )
    z0, z1 = z_range
    add_part(
        link,
        BOX,
        (width / 2, thickness / 2, (z1 - z0) / 2),
        rgba,
        pos=(s * width / 2, thickness / 2, (z0 + z1) / 2),
    )
    return link, s


def add_bottom_hinged_door(
    parent: mujoco.MjsBody,
    name: str,
    *,
    x_range: Vec,
    hinge_z: float,
    height: float,
    front_y: float,
    thickness: float,
    limits: tuple[float, float],
    rgba: Rgba,
) -> mujoco.MjsBody:
    """A drop-down door (oven, dishwasher): hinge along x at its bottom front edge, top falls toward -y.

    Link frame on the axis; the door occupies z in [0, height], y in [0, thickness] and never dips below the
    axis while opening.
    """
    link = add_moving_link(
        parent,
        name,
        (0.0, front_y, hinge_z),
        joint=f"{name}_hinge",
        joint_type=HINGE,
        axis=(1, 0, 0),
        limits=limits,
    )
    x0, x1 = x_range
    add_part(
        link,
        BOX,
        ((x1 - x0) / 2, thickness / 2, height / 2),
        rgba,
        pos=((x0 + x1) / 2, thickness / 2, height / 2),
    )
    return link


def add_lid(
    parent: mujoco.MjsBody,
    name: str,
    *,
    hinge_y: float,
    hinge_z: float,
    width: float,
    depth: float,
    thickness: float,
    limits: tuple[float, float],
    rgba: Rgba,
) -> mujoco.MjsBody:
    """A lid hinged along x at its back edge (y = hinge_y), lying toward -y, opening upward.

    Link frame on the hinge axis at the lid's bottom face; the lid occupies y in [-depth, 0],
    z in [0, thickness].
    """
    link = add_moving_link(
        parent,
        name,
        (0.0, hinge_y, hinge_z),
        joint=f"{name}_hinge",
        joint_type=HINGE,
        axis=(-1, 0, 0),
        limits=limits,
    )
    add_part(link, BOX, (width / 2, depth / 2, thickness / 2), rgba, pos=(0, -depth / 2, thickness / 2))
    return link


def add_drawer(
    parent: mujoco.MjsBody,
    name: str,
    *,
    opening: Vec,
    opening_center: Vec,
    front_y: float,
    depth: float,
    travel: float,
    front_size: Vec,
    rgba: Rgba,
    body_rgba: Rgba,
) -> mujoco.MjsBody:
    """A drawer sliding out toward -y from an opening (width, height) centred at (x, z) in a carcass whose
    front face is at y = front_y. The overlay front panel (front_size: width, height, thickness) sits in front
    of the face; the box behind it clears the opening by GAP on every side.

    Link frame at the back face of the front panel, opening centre; the joint's positive direction pulls out.
    """
    ow, oh = opening
    cx, cz = opening_center
    fw, fh, ft = front_size
    link = add_moving_link(
        parent,
        name,
        (cx, front_y - GAP, cz),
        joint=f"{name}_slide",
        joint_type=SLIDE,
        axis=(0, -1, 0),
        limits=(0.0, travel),
    )
    add_part(link, BOX, (fw / 2, ft / 2, fh / 2), rgba, pos=(0, -ft / 2, 0))
    bw, bh = ow - 2 * GAP, oh - 2 * GAP
    add_shell(link, (bw, depth, bh), 0.008, body_rgba, open_side="top", z0=-oh / 2 + GAP, y0=depth / 2 + GAP)
    return link


def set_body_mass(body: mujoco.MjsBody, total: float) -> np.ndarray:
    """Give the body's geoms masses proportional to their volumes, summing to `total`; returns the centre of
    mass in the body frame (the grasp point of rigid objects)."""
    volumes, centres = [], []
    for geom in body.geoms:
        volume, centre = _volume_and_centre(geom)
        volumes.append(volume)
        centres.append(centre)
    weights = np.asarray(volumes) / np.sum(volumes)
    for geom, w in zip(body.geoms, weights, strict=True):
        geom.mass = float(total * w)
    return weights @ np.asarray(centres)


def _volume_and_centre(geom: mujoco.MjsGeom) -> tuple[float, np.ndarray]:
    size = np.asarray(geom.size)
    if not np.isnan(geom.fromto[0]):
        a, b = np.asarray(geom.fromto[:3]), np.asarray(geom.fromto[3:])
        half_length, centre = np.linalg.norm(b - a) / 2, (a + b) / 2
    else:
        half_length, centre = size[1], np.asarray(geom.pos)
    r = size[0]
    if geom.type == BOX:
        return 8 * size[0] * size[1] * size[2], centre
    if geom.type == SPHERE:
        return 4 / 3 * math.pi * r**3, centre
    if geom.type == ELLIPSOID:
        return 4 / 3 * math.pi * size[0] * size[1] * size[2], centre
    if geom.type == CYLINDER:
        return math.pi * r**2 * 2 * half_length, centre
    if geom.type == CAPSULE:
        return math.pi * r**2 * (2 * half_length + 4 / 3 * r), centre
    raise ValueError(f"no volume rule for geom type {geom.type}")


@dataclass(frozen=True)
class Design:
    """A sampled object: `build` makes its MjSpec; names of the grasp body and the operated joint."""

    build: Callable[[], mujoco.MjSpec]
    grasp_body: str
    joint: str | None


def finish(spec: mujoco.MjSpec, category: str, link: mujoco.MjsBody, grasp: Vec) -> mujoco.MjSpec:
    """Category mass on the operated link, the grasp site, and the category's gravity setting."""
    params = CATEGORY_PARAMS[category]
    set_body_mass(link, params.mass)
    add_grasp_site(link, grasp)
    apply_gravity_setting(spec, params)
    return spec


@dataclass(frozen=True)
class Handle:
    """A sampled handle: a bar (horizontal, or vertical as fridge doors), a round knob, or a lever."""

    kind: str
    length: float
    radius: float
    standoff: float
    rgba: Rgba
    vertical: bool = False

    def add(self, link: mujoco.MjsBody, grasp: Vec, pivot_side: float = 1.0) -> None:
        """Attach with the grasp point at `grasp`; the mounting surface is `standoff` behind it (+y)."""
        if self.kind == "bar":
            add_bar_handle(
                link, grasp, self.length, self.radius, self.standoff, self.rgba, vertical=self.vertical
            )
        elif self.kind == "knob":
            add_knob(link, grasp, self.radius, self.standoff, self.rgba)
        else:
            add_lever(link, grasp, self.length, self.standoff, pivot_side, self.rgba)


# Bar lengths, knob radii and lever lengths per kind (m). Radii keep bars inside the 8 cm finger gap.
HANDLE_SIZES = {"bar": (0.08, 0.2), "knob": (0.022, 0.03), "lever": (0.1, 0.14)}


def sample_handle(
    rng: np.random.Generator,
    kinds: Sequence[str],
    *,
    length: tuple[float, float] | None = None,
    standoff: tuple[float, float] = (0.04, 0.06),
    vertical: bool = False,
) -> Handle:
    """Standoffs of 4-6 cm leave room for the fingers between the grip and the surface behind it. `length`
    overrides the bar/lever length range (knobs keep their radius range)."""
    kind = choice(rng, kinds)
    low, high = length if length is not None and kind != "knob" else HANDLE_SIZES[kind]
    size = uniform(rng, low, high)
    radius = size if kind == "knob" else uniform(rng, 0.008, 0.013)
    return Handle(kind, size, radius, uniform(rng, *standoff), colour(rng, "metal"), vertical)

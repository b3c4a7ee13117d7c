"""Two hand-made objects that exercise open/close and pick until the procedural library covers every category.

`test/box`: a storage box on the stage whose lid is hinged along its back edge; a bar handle in front of the
lid's free edge is the grasp point. `test/can`: a free rigid cylinder picked by its centre of mass.
"""

from __future__ import annotations

import math

import mujoco

from mobilemani_rl.assets.objects.categories import CATEGORY_PARAMS, ObjectKind
from mobilemani_rl.assets.objects.model import ObjectModel
from mobilemani_rl.assets.objects.parts import (
    BOX,
    CAPSULE,
    CYLINDER,
    add_grasp_site,
    add_moving_link,
    add_part,
    apply_gravity_setting,
    new_object_spec,
)

BOX_HALF = (0.15, 0.12, 0.08)  # x, y, z half extents of the box body
WALL = 0.008
LID_THICKNESS = 0.012
HANDLE_OFFSET = 0.035  # handle bar in front of the lid's free edge
WOOD = (0.62, 0.45, 0.3, 1.0)
LID = (0.7, 0.52, 0.35, 1.0)
METAL = (0.3, 0.3, 0.32, 1.0)


def build_test_box() -> mujoco.MjSpec:
    params = CATEGORY_PARAMS["box"]
    spec, root = new_object_spec("test_box")
    hx, hy, hz = BOX_HALF
    add_part(root, BOX, (hx, hy, WALL / 2), WOOD, pos=(0, 0, WALL / 2))
    for sx in (-1, 1):
        add_part(root, BOX, (WALL / 2, hy, hz), WOOD, pos=(sx * (hx - WALL / 2), 0, hz))
    for sy in (-1, 1):
        add_part(root, BOX, (hx, WALL / 2, hz), WOOD, pos=(0, sy * (hy - WALL / 2), hz))
    # Hinge along the back top edge; the lid extends toward -y (the robot) and opens upward.
    lid = add_moving_link(
        root,
        "lid",
        (0, hy, 2 * hz + LID_THICKNESS / 2),
        joint="lid_hinge",
        joint_type=mujoco.mjtJoint.mjJNT_HINGE,
        axis=(-1, 0, 0),
        limits=(0.0, math.radians(110)),
    )
    lid_mass = params.mass
    add_part(lid, BOX, (hx, hy, LID_THICKNESS / 2), LID, pos=(0, -hy, 0), mass=0.85 * lid_mass)
    bar_y = -2 * hy - HANDLE_OFFSET
    add_part(lid, CAPSULE, (0.008,), METAL, fromto=(-0.05, bar_y, 0, 0.05, bar_y, 0), mass=0.05 * lid_mass)
    for sx in (-1, 1):
        add_part(
            lid,
            BOX,
            (0.006, HANDLE_OFFSET / 2, 0.005),
            METAL,
            pos=(sx * 0.05, -2 * hy - HANDLE_OFFSET / 2, 0),
            mass=0.05 * lid_mass,
        )
    add_grasp_site(lid, (0, bar_y, 0))
    apply_gravity_setting(spec, params)
    return spec


CAN_RADIUS, CAN_HALF_HEIGHT = 0.03, 0.055


def build_test_can() -> mujoco.MjSpec:
    params = CATEGORY_PARAMS["holistic"]
    spec, root = new_object_spec("test_can")
    add_part(root, CYLINDER, (CAN_RADIUS, CAN_HALF_HEIGHT), (0.75, 0.1, 0.1, 1.0), mass=params.mass)
    add_grasp_site(root, (0, 0, 0))
    apply_gravity_setting(spec, params)
    return spec


TEST_OBJECTS: dict[str, ObjectModel] = {
    "test/box": ObjectModel(
        "test/box", "box", ObjectKind.ARTICULATED, build_test_box, grasp_body="lid", joint="lid_hinge"
    ),
    "test/can": ObjectModel("test/can", "holistic", ObjectKind.RIGID, build_test_can, grasp_body="object"),
}

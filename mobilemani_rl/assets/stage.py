"""Where the object stands in every scene: the support stage, the object's name prefix,
the episode-start pose.

One place below both the scene decoration (`assets.scenes`, which keeps rooms clear of the object) and the env
(`envs.scene`, `envs.resets`, which build and reset it), so the two cannot drift apart. Values a run may
override (such as `env.reset.pick_y_offset`) come in as arguments, never as defaults read here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mobilemani_rl.assets.objects import ObjectKind, ObjectModel, Place

if TYPE_CHECKING:  # the scenes package imports this module; a run-time import back would be a cycle
    from mobilemani_rl.assets.scenes.placements import Placement

OBJECT_PREFIX = "obj/"  # the object's element names once attached into a scene
STAGE_HALF = (2.0, 1.0, 0.5)  # the reference's 4 x 2 x 1 m support stage


def stage_top(obj: ObjectModel, placement: Placement | None) -> float:
    """Height of the object's bottom before any random lift: the table top in tabletop scenes
    (its height comes with the room), else the category's init_height."""
    if placement is not None and placement.setting is Place.TABLETOP:
        return placement.support_height
    return obj.params.init_height


def upright_position(obj: ObjectModel, top: np.ndarray) -> np.ndarray:
    """(..., 3) object root with its grasp point (at the initial joint value) over the world origin and its
    bottom on the stage top, one per stage top in `top`."""
    kin = obj.kinematics
    top = np.asarray(top, dtype=float)
    pos = np.zeros((*top.shape, 3))
    pos[..., :2] = -kin.handle_closed[:2]
    pos[..., 2] = top - kin.bottom_z
    return pos


def pick_shift(obj: ObjectModel, pick_y_offset: float) -> float:
    """How much further back (+y) than `upright_position` the object starts: rigid objects by `pick_y_offset`
    (0.1 m in the reference), the others not at all."""
    return pick_y_offset if obj.kind is ObjectKind.RIGID else 0.0


def object_position(obj: ObjectModel, top: np.ndarray, pick_y_offset: float) -> np.ndarray:
    """(..., 3) object root at an episode start, before any random yaw."""
    pos = upright_position(obj, top)
    pos[..., 1] += pick_shift(obj, pick_y_offset)
    return pos


def stage_position(front: np.ndarray, top: np.ndarray) -> np.ndarray:
    """(..., 3) stage centre for a stage whose front face is at y = `front` and whose top is at z = `top`."""
    front = np.asarray(front, dtype=float)
    return np.stack((np.zeros_like(front), front + STAGE_HALF[1], top - STAGE_HALF[2]), axis=-1)

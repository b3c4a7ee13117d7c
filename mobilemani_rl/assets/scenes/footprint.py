"""Where the object stands at the start of an episode, as an axis-aligned world box.

The env's placement (mobilemani_rl/assets/stage.py), widened by the motion an episode start may add: rigid
objects spin up to ±90° about the vertical, carts travel ±CART_TRAVEL in y.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mobilemani_rl.assets.objects import ObjectKind, ObjectModel
from mobilemani_rl.assets.objects.model import CART_TRAVEL
from mobilemani_rl.assets.scenes.placements import Placement
from mobilemani_rl.assets.stage import pick_shift, stage_top, upright_position

CORNERS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)


@dataclass(frozen=True)
class Footprint:
    lo: np.ndarray  # (3,) world min corner
    hi: np.ndarray  # (3,) world max corner

    @property
    def half_width(self) -> float:
        """Half extent in x about the world origin (the slot centre)."""
        return float(max(-self.lo[0], self.hi[0]))


def local_bounds(obj: ObjectModel) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of every geom (visual ones included) in the object's root frame, joint at its initial value."""
    model = obj.build_spec().compile()
    data = mujoco.MjData(model)
    if obj.joint is not None:
        data.qpos[model.joint(obj.joint).qposadr[0]] = obj.kinematics.init_value
    mujoco.mj_kinematics(model, data)
    points = []
    for g in range(model.ngeom):
        center, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
        points.append((CORNERS * half + center) @ data.geom_xmat[g].reshape(3, 3).T + data.geom_xpos[g])
    stacked = np.concatenate(points)
    return stacked.min(axis=0), stacked.max(axis=0)


def object_footprint(obj: ObjectModel, placement: Placement, pick_y_offset: float) -> Footprint:
    """`pick_y_offset`: the running reset config's (env.reset.pick_y_offset)."""
    lo, hi = local_bounds(obj)
    origin = upright_position(obj, stage_top(obj, placement))
    lo, hi = lo + origin, hi + origin
    if obj.kind is ObjectKind.RIGID:
        # The box at the start position (pick_shift behind the upright one), widened to a circle for the yaw.
        radius = float(np.max(np.linalg.norm(CORNERS[:, :2] * (hi - lo)[:2] / 2, axis=1)))
        centre = (lo + hi)[:2] / 2 + (0.0, pick_shift(obj, pick_y_offset))
        lo[:2], hi[:2] = centre - radius, centre + radius
    elif obj.kind is ObjectKind.CART:
        lo[1] -= CART_TRAVEL
        hi[1] += CART_TRAVEL
    return Footprint(lo, hi)

"""The object interface every generator returns, and the object-frame kinematics the environment needs."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.categories import (
    CATEGORY_PARAMS,
    SKILLS_BY_KIND,
    CategoryParams,
    ObjectKind,
)

GRASP_SITE = "grasp"
ROOT_BODY = "object"
OPEN_ANGLE = np.radians(60.0)  # revolute joints open to lower + 60°, as in the reference
OPEN_RATIO = 0.6  # prismatic joints open to 60 % of their range
CLOSE_START = (np.radians(40.0), np.radians(80.0))  # close tasks start 40–80° open (revolute)
CLOSE_START_RATIO = (0.4, 0.8)  # ... or 40–80 % open (prismatic)
PICK_LIFT = 0.2
CART_TRAVEL = 0.3


@dataclass(frozen=True)
class ObjectModel:
    """One procedural object.

    `build_spec` returns an MjSpec whose worldbody holds a single root body named `object` in the object's own
    frame (front, where the robot stands, toward -y; bottom at z = 0 after placement). Articulated objects
    have a fixed root (made a mocap body by the scene) and one operated joint `joint`; carts and rigid objects
    get a free joint from the scene. A site named `grasp` on `grasp_body` marks the grasp point
    (handle, lid edge, cart handle, or a rigid object's centre of mass).
    """

    object_id: str
    category: str
    kind: ObjectKind
    build_spec: Callable[[], mujoco.MjSpec]
    grasp_body: str
    joint: str | None = None
    split: str | None = None  # "train" / "test" for catalog objects

    @property
    def params(self) -> CategoryParams:
        return CATEGORY_PARAMS[self.category]

    @property
    def skills(self) -> tuple[str, ...]:
        return SKILLS_BY_KIND[self.kind]

    @cached_property
    def kinematics(self) -> ObjectKinematics:
        return ObjectKinematics.from_model(self)


@dataclass(frozen=True)
class ObjectKinematics:
    """Object-frame facts computed once by compiling the object alone."""

    joint_range: tuple[float, float]
    joint_is_hinge: bool
    init_value: float  # joint value at the start of open tasks (lower + init_joint offset)
    open_value: float  # the reference's "opened" joint value: lower + 60° (capped) or 60 % of the range
    goal_value: float  # joint value whose handle position is the open goal (see `from_model`)
    handle_closed: np.ndarray  # grasp point in the root frame with the joint at init_value
    handle_opened: np.ndarray  # grasp point in the root frame with the joint at goal_value: the open goal
    goal_distance: float  # D0, the reward's distance scale: |handle at open_value - handle at lower|
    bottom_z: float  # lowest point of the object's collision geometry, root frame, joint at init_value
    front_y: float  # most negative y of the object's collision geometry (its face toward the robot)

    @classmethod
    def from_model(cls, obj: ObjectModel) -> ObjectKinematics:
        model = obj.build_spec().compile()
        data = mujoco.MjData(model)
        if obj.joint is None:
            lower = upper = init = opened = 0.0
            is_hinge = False
        else:
            joint = model.joint(obj.joint)
            lower, upper = (float(v) for v in joint.range)
            is_hinge = joint.type[0] == mujoco.mjtJoint.mjJNT_HINGE
            init = min(lower + obj.params.init_joint, upper)
            opened = (
                min(lower + float(OPEN_ANGLE), upper) if is_hinge else lower + OPEN_RATIO * (upper - lower)
            )
        # The reference stores the opened handle in the link's frame at the lower limit and places it with the
        # link's pose at reset, which starts init - lower past the limit: the goal is the handle at
        # opened + (init - lower), ~70° for the lids that start 10° open, not capped at the upper limit.
        goal = opened + (init - lower)
        distance = float(
            np.linalg.norm(
                _grasp_point(model, data, obj.joint, opened) - _grasp_point(model, data, obj.joint, lower)
            )
        )
        opened_pos = _grasp_point(model, data, obj.joint, goal)
        closed_pos = _grasp_point(model, data, obj.joint, init)
        low, front = _extent(model, data)  # with the joint at init_value
        return cls((lower, upper), is_hinge, init, opened, goal, closed_pos, opened_pos, distance, low, front)

    def close_start_range(self) -> tuple[float, float]:
        """Joint values a close task starts between, as in the reference: 40–80° or 40–80 % open."""
        lower, upper = self.joint_range
        if self.joint_is_hinge:
            return min(lower + CLOSE_START[0], upper), min(lower + CLOSE_START[1], upper)
        span = upper - lower
        return lower + CLOSE_START_RATIO[0] * span, lower + CLOSE_START_RATIO[1] * span


def _grasp_point(model: mujoco.MjModel, data: mujoco.MjData, joint: str | None, value: float) -> np.ndarray:
    if joint is not None:
        data.qpos[model.joint(joint).qposadr[0]] = value
    mujoco.mj_kinematics(model, data)
    return data.site(GRASP_SITE).xpos.copy()


def _extent(model: mujoco.MjModel, data: mujoco.MjData) -> tuple[float, float]:
    """Lowest z and most negative y over the collision geoms' bounding boxes (current kinematics)."""
    low, front = np.inf, np.inf
    for g in range(model.ngeom):
        if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0:
            continue
        center, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
        rot = data.geom_xmat[g].reshape(3, 3)
        corners = (
            np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half + center
        )
        world = corners @ rot.T + data.geom_xpos[g]
        low, front = min(low, world[:, 2].min()), min(front, world[:, 1].min())
    return float(low), float(front)

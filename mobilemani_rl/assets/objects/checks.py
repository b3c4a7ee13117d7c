"""Geometric and physical checks of one object on its support stage (used by tests and scripts).

- `sweep`: drive the object kinematically from its start to the skill's goal and report the grasp-point error
  at the end and every penetrating contact of a moving part with the rest of the object, the stage or the
  ground along the way (parent/child filtering off, so a door scraping its own carcass counts).
- `rest_drift`, `push_travel`: simulate a free object (holistic, cart) on the stage under gravity.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.categories import ObjectKind
from mobilemani_rl.assets.objects.model import CART_TRAVEL, GRASP_SITE, PICK_LIFT, ROOT_BODY, ObjectModel
from mobilemani_rl.assets.stage import OBJECT_PREFIX, STAGE_HALF, stage_position

PENETRATION = 1e-4  # m; touching surfaces (distance ~0) are not collisions
STAGE_SHIFT = 0.1  # the stage front reaches this far in front of the object at most (reset range)
TIMESTEP = 1.0 / 120.0  # the env's physics step (30 Hz control, 4 substeps)


@dataclass(frozen=True)
class SweepResult:
    goal_error: float  # m, grasp point to the skill's goal at the end of the sweep
    collisions: tuple[tuple[str, str, float], ...]  # (body, other body, depth) per penetrating contact


def stage_model(obj: ObjectModel) -> mujoco.MjModel:
    """The object with its bottom on a 4 x 2 x 1 m stage (top at z = 0), stage front at the object's front
    minus the largest reset shift, ground under the stage; free objects get a free joint."""
    kin = obj.kinematics
    spec = mujoco.MjSpec()
    spec.option.timestep = TIMESTEP
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.iterations = 20
    ground = -obj.params.init_height
    spec.worldbody.add_geom(
        name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 5, 0.1], pos=[0, 0, ground]
    )
    spec.worldbody.add_geom(
        name="stage",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=list(STAGE_HALF),
        pos=stage_position(kin.front_y - STAGE_SHIFT, 0.0),
    )
    frame = spec.worldbody.add_frame(pos=[0, 0, -kin.bottom_z])
    spec.attach(obj.build_spec(), prefix=OBJECT_PREFIX, frame=frame)
    if obj.kind is not ObjectKind.ARTICULATED:
        spec.body(OBJECT_PREFIX + ROOT_BODY).add_freejoint(name=OBJECT_PREFIX + "free")
    model = spec.compile()
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_FILTERPARENT
    return model


def _penetrations(
    model: mujoco.MjModel, data: mujoco.MjData, moving: set[int]
) -> list[tuple[str, str, float]]:
    mujoco.mj_kinematics(model, data)
    mujoco.mj_collision(model, data)
    found = []
    for c in data.contact[: data.ncon]:
        bodies = [int(model.geom_bodyid[g]) for g in c.geom]
        if c.dist < -PENETRATION and moving.intersection(bodies) and bodies[0] != bodies[1]:
            found.append((model.body(bodies[0]).name, model.body(bodies[1]).name, float(-c.dist)))
    return found


def sweep(obj: ObjectModel, skill: str, steps: int = 30) -> SweepResult:
    """Kinematic sweep from the start of `skill` (open: init value; close: the widest close start) to its
    goal."""
    kin = obj.kinematics
    model = stage_model(obj)
    data = mujoco.MjData(model)
    offset = np.array([0.0, 0.0, -kin.bottom_z])
    site = model.site(OBJECT_PREFIX + GRASP_SITE).id
    collisions: list[tuple[str, str, float]] = []
    if obj.kind is ObjectKind.ARTICULATED:
        qadr = model.joint(OBJECT_PREFIX + obj.joint).qposadr[0]
        moving = {b for b in range(model.nbody) if model.body_jntnum[b] > 0 or _has_moving_parent(model, b)}
        # One path from the initial value to the widest close start covers both skills' sweeps.
        widest = max(kin.goal_value, kin.close_start_range()[1])
        for q in np.linspace(kin.init_value, widest, steps):
            data.qpos[qadr] = q
            collisions += _penetrations(model, data, moving)
        data.qpos[qadr] = kin.goal_value if skill == "open" else kin.init_value
        goal = kin.handle_opened if skill == "open" else kin.handle_closed
    else:
        root = model.body(OBJECT_PREFIX + ROOT_BODY).id
        moving = {b for b in range(model.nbody) if model.body_rootid[b] == root}
        qadr = model.joint(OBJECT_PREFIX + "free").qposadr[0]
        delta = {"pick": (0, 0, PICK_LIFT), "pull": (0, -CART_TRAVEL, 0), "push": (0, CART_TRAVEL, 0)}[skill]
        goal = kin.handle_closed + np.asarray(delta)
        # The bottom rests on the stage (touching) along the whole path for carts, and leaves it when picked.
        for t in np.linspace(0.0, 1.0, steps):
            data.qpos[qadr : qadr + 3] = offset + t * np.asarray(delta)
            collisions += _penetrations(model, data, moving)
    mujoco.mj_kinematics(model, data)
    error = float(np.linalg.norm(data.site_xpos[site] - (goal + offset)))
    return SweepResult(error, tuple(collisions))


def _has_moving_parent(model: mujoco.MjModel, body: int) -> bool:
    while body > 0:
        if model.body_jntnum[body] > 0:
            return True
        body = model.body_parentid[body]
    return False


def rest_drift(obj: ObjectModel, seconds: float = 2.0) -> float:
    """Displacement (m) of a free object's grasp point after resting on the stage for `seconds`."""
    model = stage_model(obj)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    site = model.site(OBJECT_PREFIX + GRASP_SITE).id
    start = data.site_xpos[site].copy()
    mujoco.mj_step(model, data, nstep=int(round(seconds / model.opt.timestep)))
    return float(np.linalg.norm(data.site_xpos[site] - start))


def push_travel(obj: ObjectModel, force: np.ndarray, push_seconds: float, coast_seconds: float) -> float:
    """Displacement (m) of a free object's grasp point after a force at its grasp point for `push_seconds`
    and then `coast_seconds` without it."""
    model = stage_model(obj)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    site = model.site(OBJECT_PREFIX + GRASP_SITE).id
    root = model.body(OBJECT_PREFIX + ROOT_BODY).id
    start = data.site_xpos[site].copy()
    for _ in range(int(round(push_seconds / model.opt.timestep))):
        data.xfrc_applied[:] = 0.0
        # A force at the grasp point: the wrench about the root's centre of mass.
        arm = data.site_xpos[site] - data.xipos[root]
        data.xfrc_applied[root, :3] = force
        data.xfrc_applied[root, 3:] = np.cross(arm, force)
        mujoco.mj_step(model, data)
    data.xfrc_applied[:] = 0.0
    mujoco.mj_step(model, data, nstep=int(round(coast_seconds / model.opt.timestep)))
    return float(np.linalg.norm(data.site_xpos[site] - start))

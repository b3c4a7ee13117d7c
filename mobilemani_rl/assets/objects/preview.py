"""Offscreen renders of single objects (closed and opened) and a contact sheet of samples per category."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.catalog import CATALOG, CATEGORIES, catalog_ids
from mobilemani_rl.assets.objects.model import ROOT_BODY, ObjectModel

FLOOR_RGBA = [0.82, 0.82, 0.8, 1]


def preview_model(obj: ObjectModel) -> mujoco.MjModel:
    """The object alone, bottom on a floor, lit from the front (-y) where the robot stands."""
    spec = mujoco.MjSpec()
    spec.visual.global_.offwidth, spec.visual.global_.offheight = 640, 640
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[5, 5, 0.1], rgba=FLOOR_RGBA)
    spec.worldbody.add_light(pos=[0, -2, 3], dir=[0, 0.6, -0.8], diffuse=[0.7, 0.7, 0.7], castshadow=False)
    spec.worldbody.add_light(pos=[1, -1, 2], dir=[-0.4, 0.4, -0.8], diffuse=[0.3, 0.3, 0.3], castshadow=False)
    frame = spec.worldbody.add_frame(pos=[0, 0, -obj.kinematics.bottom_z])
    spec.attach(obj.build_spec(), prefix="obj/", frame=frame)
    return spec.compile()


def render_object(obj: ObjectModel, opened: bool, size: int = 320) -> np.ndarray:
    """RGB image of the object with its operated joint at the initial or the open value (3/4 front view)."""
    model = preview_model(obj)
    data = mujoco.MjData(model)
    if obj.joint is not None:
        kin = obj.kinematics
        data.qpos[model.joint("obj/" + obj.joint).qposadr[0]] = kin.goal_value if opened else kin.init_value
    mujoco.mj_forward(model, data)
    root = model.body("obj/" + ROOT_BODY).id
    geoms = [g for g in range(model.ngeom) if model.body_rootid[model.geom_bodyid[g]] == root]
    low = np.min([data.geom_xpos[g] - model.geom_rbound[g] for g in geoms], axis=0)
    high = np.max([data.geom_xpos[g] + model.geom_rbound[g] for g in geoms], axis=0)
    camera = mujoco.MjvCamera()
    camera.lookat[:] = (low + high) / 2
    camera.distance = 1.3 * float(np.max(high - low)) + 0.15
    camera.azimuth, camera.elevation = (60.0, -22.0) if obj.joint is None or not opened else (55.0, -25.0)
    with mujoco.Renderer(model, size, size) as renderer:
        renderer.update_scene(data, camera)
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = False
        return renderer.render().copy()


def contact_sheet(out: Path, per_category: int = 3, size: int = 200, seed: int = 0) -> Path:
    """A grid: one row per category, `per_category` sample objects, each closed then opened."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(seed)
    cols = 2 * per_category
    fig, axes = plt.subplots(len(CATEGORIES), cols, figsize=(cols * 1.6, len(CATEGORIES) * 1.7))
    for row, category in enumerate(CATEGORIES):
        ids = rng.choice(catalog_ids(category), size=per_category, replace=False)
        for k, oid in enumerate(sorted(ids)):
            for opened in (False, True):
                ax = axes[row, 2 * k + int(opened)]
                ax.imshow(render_object(CATALOG[oid], opened, size))
                ax.set_title(f"{oid} {'open' if opened else 'init'}", fontsize=6)
                ax.axis("off")
    fig.tight_layout(pad=0.2)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out

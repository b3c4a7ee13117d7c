"""Room repainting for exported episodes: only the room's colours and lights change, seeded, and undone."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from mobilemani_rl.assets.objects import get_object
from mobilemani_rl.assets.robots import get_robot
from mobilemani_rl.assets.scenes import TABLE_BODY, get_placement
from mobilemani_rl.envs.config import PhysicsCfg, ResetCfg
from mobilemani_rl.envs.scene import build_scene
from mobilemani_rl.render import CameraRenderCfg, CameraRenderer
from mobilemani_rl.render.appearance import RoomRepainter
from mobilemani_rl.render.segmentation import subtree


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    built, _ = build_scene(
        get_robot("g1"), get_object("test/box"), PhysicsCfg(), ResetCfg(), get_placement("tabletop/00")
    )
    return built


def colours(model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return model.geom_rgba.copy(), model.mat_rgba.copy(), model.light_diffuse.copy()


def test_repaint_changes_only_the_room_and_restores(model: mujoco.MjModel) -> None:
    built = colours(model)
    painter = RoomRepainter(model)
    assert len(painter.geoms) + len(painter.materials) > 20 and len(painter.lights) > 0
    painter.repaint(np.random.default_rng(0), 0.5)
    geom_rgba, mat_rgba, diffuse = colours(model)
    changed_geoms = np.flatnonzero(np.any(geom_rgba != built[0], axis=1))
    changed_mats = np.flatnonzero(np.any(mat_rgba != built[1], axis=1))
    assert set(changed_geoms) <= set(painter.geoms) and len(changed_geoms) > 0.9 * len(painter.geoms)
    assert set(changed_mats) <= set(painter.materials) and len(changed_mats) > 0.9 * len(painter.materials)
    # no robot or object geom uses a room material, so their colours are untouched
    room_bodies = {int(model.geom_bodyid[g]) for g in painter.geoms}
    other = [g for g in range(model.ngeom) if model.geom_bodyid[g] not in room_bodies]
    assert not set(model.geom_matid[other]) & set(changed_mats)
    np.testing.assert_array_equal(geom_rgba[:, 3], built[0][:, 3])  # alpha kept
    assert np.all((mat_rgba >= 0) & (mat_rgba <= 1)) and not np.array_equal(diffuse, built[2])
    painter.restore()
    for now, before in zip(colours(model), built, strict=True):
        np.testing.assert_array_equal(now, before)


def test_repaint_is_seeded_and_strength_zero_keeps_the_room(model: mujoco.MjModel) -> None:
    built = colours(model)
    painter = RoomRepainter(model)
    painter.repaint(np.random.default_rng(7), 0.5)
    first = colours(model)
    painter.repaint(np.random.default_rng(3), 0.5)
    painter.repaint(np.random.default_rng(7), 0.5)  # from the built colours, not on top of the last repaint
    for now, before in zip(colours(model), first, strict=True):
        np.testing.assert_array_equal(now, before)
    painter.repaint(np.random.default_rng(7), 0.0)
    for now, before in zip(colours(model), built, strict=True):
        np.testing.assert_array_equal(now, before)
    with pytest.raises(ValueError, match="strength"):
        painter.repaint(np.random.default_rng(0), 1.5)
    painter.restore()


def test_repainted_room_renders_differently(model: mujoco.MjModel) -> None:
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    painter = RoomRepainter(model)
    head = get_robot("g1").head_camera
    with CameraRenderer(model, CameraRenderCfg(width=64, height=64, cameras=(head,))) as renderer:
        built = renderer.render(data)[head]
        painter.repaint(np.random.default_rng(1), 0.5)
        repainted = renderer.render(data)[head]
        painter.restore()
    background = built.segmentation == 0
    diff = np.abs(built.rgb.astype(int) - repainted.rgb.astype(int)).max(axis=2)
    assert diff[background].mean() > 5  # the room looks different
    np.testing.assert_array_equal(built.depth, repainted.depth)  # geometry unchanged


def test_a_table_of_its_own_is_repainted_with_the_room() -> None:
    """With a per-episode table height the table is a body of its own; its colours still change with the
    room's, so that they do not name the room either."""
    built, _ = build_scene(
        get_robot("g1"),
        get_object("test/box"),
        PhysicsCfg(),
        ResetCfg(table_height_jitter=0.1),
        get_placement("tabletop/00"),
    )
    table = subtree(built, built.body(TABLE_BODY).id)
    painter = RoomRepainter(built)
    table_geoms = np.flatnonzero(table[built.geom_bodyid])
    painted = set(painter.geoms) | {
        g for g in table_geoms if built.geom_matid[g] >= 0 and built.geom_matid[g] in set(painter.materials)
    }
    assert len(table_geoms) > 0 and set(table_geoms) <= painted

"""Scene placements: registry, determinism, every scene compiles, rooms stay visual and clear of the robot."""

import mujoco
import numpy as np
import pytest

from mobilemani_rl.assets.objects import OBJECTS, Place, get_object
from mobilemani_rl.assets.robots import get_robot
from mobilemani_rl.assets.scenes import (
    HIDDEN_GROUP,
    PLACEMENTS,
    ROOM_BODY,
    add_scene,
    get_placement,
    placements_for,
    sample_room_offsets,
    scene_ids,
)
from mobilemani_rl.assets.scenes.footprint import object_footprint
from mobilemani_rl.envs.config import PhysicsCfg, ResetCfg
from mobilemani_rl.envs.scene import build_scene_spec
from mobilemani_rl.envs.scene_sheet import showcase_object
from mobilemani_rl.utils.errors import UnknownNameError

ROBOT_START = (np.array([-0.25, -1.5]), np.array([0.25, -0.75]))  # robot root xy range at reset
BASE_RADIUS = 0.3
ROBOT_HEIGHT = 2.0
PICK_Y_OFFSET = ResetCfg().pick_y_offset  # the env's default reset


def decorated(scene_id: str, object_id: str) -> tuple[mujoco.MjModel, mujoco.MjData]:
    obj = get_object(object_id)
    spec = build_scene_spec(get_robot("g1"), obj, PhysicsCfg())
    placement = get_placement(scene_id)
    add_scene(spec, placement, obj, PICK_Y_OFFSET)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    return model, data


def object_for(scene_id: str) -> str:
    return showcase_object(get_placement(scene_id)).object_id


def room_geoms(model: mujoco.MjModel) -> np.ndarray:
    room = model.body(ROOM_BODY).id
    inside = np.zeros(model.nbody, dtype=bool)
    for body in range(model.nbody):
        inside[body] = body == room or (body > room and inside[model.body_parentid[body]])
    return np.flatnonzero(inside[model.geom_bodyid])


def world_boxes(
    model: mujoco.MjModel, data: mujoco.MjData, geoms: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    lo, hi = [], []
    for g in geoms:
        local = corners * model.geom_aabb[g, 3:] + model.geom_aabb[g, :3]
        world = local @ data.geom_xmat[g].reshape(3, 3).T + data.geom_xpos[g]
        lo.append(world.min(axis=0))
        hi.append(world.max(axis=0))
    return np.array(lo), np.array(hi)


def test_registry_has_16_train_and_4_test_scenes_per_setting():
    assert len(PLACEMENTS) == 100
    for setting in Place:
        assert len(scene_ids(setting, "train")) == 16 and len(scene_ids(setting, "test")) == 4
    assert get_placement("tabletop/07").split == "train" and get_placement("door/17").split_index == 1
    heights = [p.support_height for p in PLACEMENTS.values() if p.setting is Place.TABLETOP]
    assert min(heights) >= 0.22 and max(heights) <= 0.76 and len(set(heights)) > 10
    assert {p.style for p in PLACEMENTS.values()} == {
        "kitchen",
        "bedroom",
        "office",
        "hospital",
        "warehouse",
        "parking_lot",
    }


def test_unknown_scene_names_the_valid_ones():
    # one span per setting: the hundred ids buried the error
    with pytest.raises(
        UnknownNameError,
        match="unknown scene 'kitchen/3'; valid scenes: tabletop/00 to tabletop/19, wall/00 to wall/19, "
        "door/00 to door/19, outdoor/00 to outdoor/19, space/00 to space/19$",
    ):
        get_placement("kitchen/3")


def test_object_in_the_wrong_setting_is_refused_with_its_scenes():
    obj = get_object("test/box")
    spec = build_scene_spec(get_robot("g1"), obj, PhysicsCfg())
    with pytest.raises(ValueError, match="valid scenes: tabletop/00"):
        add_scene(spec, get_placement("wall/00"), obj, PICK_Y_OFFSET)
    assert [p.setting for p in placements_for(obj)] == [Place.TABLETOP] * 20


def test_footprint_follows_the_running_pick_offset():
    """Rooms keep clear of where the run's env.reset.pick_y_offset puts rigid objects, not the default."""
    obj, placement = get_object("test/can"), get_placement("tabletop/00")
    near, far = (object_footprint(obj, placement, offset) for offset in (0.1, 0.4))
    np.testing.assert_allclose(far.lo - near.lo, [0.0, 0.3, 0.0], atol=1e-12)
    np.testing.assert_allclose(far.hi - near.hi, [0.0, 0.3, 0.0], atol=1e-12)


def test_scenes_are_deterministic_and_distinct():
    first, _ = decorated("tabletop/03", "test/box")
    again, _ = decorated("tabletop/03", "test/box")
    other, _ = decorated("tabletop/04", "test/box")
    assert first.ngeom == again.ngeom
    np.testing.assert_array_equal(first.geom_pos, again.geom_pos)
    np.testing.assert_array_equal(first.geom_rgba, again.geom_rgba)
    np.testing.assert_array_equal(first.tex_data, again.tex_data)
    assert first.ngeom != other.ngeom or not np.array_equal(first.geom_rgba, other.geom_rgba)


def assert_room_is_visual_and_clear(scene_id: str, object_id: str) -> None:
    model, data = decorated(scene_id, object_id)
    geoms = room_geoms(model)
    assert len(geoms) > 30
    assert not model.geom_contype[geoms].any() and not model.geom_conaffinity[geoms].any()
    assert model.body_mocapid[model.body(ROOM_BODY).id] >= 0
    for name in ("stage", "ground"):  # invisible but still physical
        geom = model.geom(name)
        assert geom.group[0] == HIDDEN_GROUP and geom.contype[0] != 0
    lo, hi = world_boxes(model, data, geoms)
    # Floors, rugs and road markings lie under the wheels; ceilings and their lamps far above the head.
    raised = (hi[:, 2] > 0.01) & (lo[:, 2] < ROBOT_HEIGHT)
    robot_lo, robot_hi = ROBOT_START[0] - BASE_RADIUS, ROBOT_START[1] + BASE_RADIUS
    hits_robot = raised & np.all(lo[:, :2] < robot_hi, axis=1) & np.all(hi[:, :2] > robot_lo, axis=1)
    assert not hits_robot.any(), f"{scene_id}: room geoms {geoms[hits_robot]} in the robot's start area"
    foot = object_footprint(get_object(object_id), get_placement(scene_id), PICK_Y_OFFSET)
    margin = 0.01  # the table top touches the object's bottom
    hits_object = np.all(lo < foot.hi - margin, axis=1) & np.all(hi > foot.lo + margin, axis=1)
    assert not hits_object.any(), f"{scene_id}: room geoms {geoms[hits_object]} inside {object_id}"


@pytest.mark.parametrize("scene_id", list(PLACEMENTS))
def test_every_scene_compiles_visual_only_and_clear_of_robot_and_object(scene_id):
    assert_room_is_visual_and_clear(scene_id, object_for(scene_id))


def test_room_offsets_follow_the_reference_jitter():
    offsets = sample_room_offsets(np.random.default_rng(0), 1000)
    assert offsets.shape == (1000, 3) and not offsets[:, 2].any()
    assert np.abs(offsets[:, 0]).max() <= 0.1 and np.abs(offsets[:, 1]).max() <= 0.05


@pytest.mark.slow
@pytest.mark.parametrize("object_id", sorted(OBJECTS))
def test_every_registry_object_fits_all_scenes_of_its_setting(object_id):
    for placement in placements_for(get_object(object_id)):
        assert_room_is_visual_and_clear(placement.scene_id, object_id)

"""The scripted teacher still succeeds in realistic rooms (visual only; the table sets the height)."""

import mujoco
import numpy as np
import pytest

from mobilemani_rl.assets.scenes import ROOM_BODY, TABLE_BODY, scene_ids
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.rollout import first_episode_success
from mobilemani_rl.render.segmentation import subtree
from mobilemani_rl.scripted.policy import ScriptedPolicy


def realistic_success(scene_id: str, robot: str, obj: str, skill: str, episodes: int) -> float:
    env = MobileManiEnv(EnvCfg(num_envs=episodes, seed=0, task=TaskCfg(robot, obj, skill, scene=scene_id)))
    return float(first_episode_success(env, ScriptedPolicy(env), seed=0).mean())


@pytest.mark.parametrize("scene_id", ["tabletop/00", "tabletop/17"])
def test_g1_opens_the_box_on_a_train_and_a_test_table(scene_id):
    assert realistic_success(scene_id, "g1", "test/box", "open", 16) >= 0.7


def test_object_stands_on_the_placement_table():
    env = MobileManiEnv(EnvCfg(num_envs=2, task=TaskCfg("g1", "test/box", "open", scene="tabletop/05")))
    env.reset(seed=0)
    stage_top = env.view.mocap_pos[:, env.index.stage_mocap, 2] + 0.5  # stage half height
    assert abs(stage_top - env.placement.support_height).max() < 1e-9
    room = env.model.body_pos[env.model.body(ROOM_BODY).id]
    offsets = env.view.mocap_pos[:, env.room_mocap] - room
    assert (
        np.all(np.abs(offsets[:, 0]) <= 0.1)
        and np.all(np.abs(offsets[:, 1]) <= 0.05)
        and np.ptp(offsets[:, 0]) > 0
    )


def test_table_height_jitter_moves_table_object_and_stage_together():
    """Each episode's table top, the invisible stage the object stands on, and the object itself are raised or
    lowered by one offset within +-jitter; the room stays where the reference puts it."""
    jitter = 0.1
    cfg = EnvCfg(num_envs=16, seed=0, task=TaskCfg("g1", "test/box", "open", scene="tabletop/05"))
    cfg.reset.recording, cfg.reset.table_height_jitter = True, jitter
    env = MobileManiEnv(cfg)
    env.reset(seed=0)
    model, height = env.model, env.placement.support_height
    stage_top = env.view.mocap_pos[:, env.index.stage_mocap, 2] + 0.5  # stage half height
    offset = stage_top - height
    assert np.all(np.abs(offset) <= jitter) and np.ptp(offset) > jitter
    table = env.view.mocap_pos[:, env.table_mocap] - model.body_pos[model.body(TABLE_BODY).id]
    room = env.view.mocap_pos[:, env.room_mocap] - model.body_pos[model.body(ROOM_BODY).id]
    np.testing.assert_allclose(table[:, :2], room[:, :2])  # the table goes with the room's jitter
    np.testing.assert_allclose(table[:, 2], offset, atol=1e-12)
    np.testing.assert_array_equal(room[:, 2], 0.0)
    geoms = np.flatnonzero(subtree(model, model.body(TABLE_BODY).id)[model.geom_bodyid])
    # half heights: a box's third size, a cylinder's (a leg's) second
    half = np.where(model.geom_type[geoms] == mujoco.mjtGeom.mjGEOM_BOX, *model.geom_size[geoms, 2:0:-1].T)
    for i in range(env.num_envs):
        z = env.batch.get_data(i).geom_xpos[geoms, 2]
        assert (z + half).max() == pytest.approx(stage_top[i], abs=1e-6)
        assert (z - half).min() <= 1e-9  # the legs still reach the floor
    baseline = MobileManiEnv(EnvCfg(num_envs=1, task=TaskCfg("g1", "test/box", "open", scene="tabletop/05")))
    assert baseline.table_mocap == -1 and model.nmocap == baseline.model.nmocap + 1


@pytest.mark.slow
@pytest.mark.parametrize(
    ("robot", "obj", "skill", "minimum"),
    [
        ("g1", "test/box", "open", 0.8),
        ("g1", "test/can", "pick", 0.7),
        ("xhand", "test/box", "open", 0.8),
    ],
)
def test_scripted_success_over_all_tabletop_scenes(robot, obj, skill, minimum):
    rates = [realistic_success(sid, robot, obj, skill, 16) for sid in scene_ids("tabletop")]
    assert sum(rates) / len(rates) >= minimum, rates

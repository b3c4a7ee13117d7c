"""The env against the reference: open goal and D0, joint acceleration, XHand self-collision."""

import itertools

import mujoco
import numpy as np
import pytest

from mobilemani_rl.assets.collision import HAND_BIT
from mobilemani_rl.assets.objects import CATALOG, get_object
from mobilemani_rl.assets.objects.model import GRASP_SITE, OPEN_ANGLE
from mobilemani_rl.assets.robots.g1 import build_g1_spec
from mobilemani_rl.assets.robots.xhand import build_xhand_spec
from mobilemani_rl.envs.config import EnvCfg, PhysicsCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv


def _link_pose_and_grasp(model: mujoco.MjModel, data: mujoco.MjData, joint: str, value: float):
    data.qpos[model.joint(joint).qposadr[0]] = value
    mujoco.mj_kinematics(model, data)
    site = model.site(GRASP_SITE)
    body = site.bodyid[0]
    return data.xpos[body].copy(), data.xmat[body].reshape(3, 3).copy(), data.site_xpos[site.id].copy()


def test_open_goal_and_d0_of_test_box_follow_the_reference_construction():
    """Reference: handle positions are stored in the grasp link's frame at the lower limit; the open goal is
    the link pose at reset (init = lower + 10°) applied to the opened handle (lower + 60°); D0 is the distance
    between the opened and the closed (lower) handle."""
    obj = get_object("test/box")
    kin = obj.kinematics
    model = obj.build_spec().compile()
    data = mujoco.MjData(model)
    lower = kin.joint_range[0]
    assert kin.init_value == pytest.approx(lower + np.radians(10.0))
    pos_low, rot_low, closed = _link_pose_and_grasp(model, data, obj.joint, lower)
    _, _, opened = _link_pose_and_grasp(model, data, obj.joint, lower + OPEN_ANGLE)
    local_opened = rot_low.T @ (opened - pos_low)
    pos_init, rot_init, _ = _link_pose_and_grasp(model, data, obj.joint, kin.init_value)
    np.testing.assert_allclose(kin.handle_opened, pos_init + rot_init @ local_opened, atol=1e-9)
    assert kin.goal_distance == pytest.approx(np.linalg.norm(opened - closed), abs=1e-9)
    # The goal is the handle ~70° open, a few centimetres past the 60° one.
    assert np.linalg.norm(kin.handle_opened - opened) > 0.03


def test_open_goal_of_a_category_without_initial_opening_is_the_opened_handle():
    obj = next(o for o in CATALOG.values() if o.joint is not None and o.params.init_joint == 0.0)
    kin = obj.kinematics
    assert kin.goal_value == kin.open_value
    model = obj.build_spec().compile()
    _, _, opened = _link_pose_and_grasp(model, mujoco.MjData(model), obj.joint, kin.open_value)
    np.testing.assert_allclose(kin.handle_opened, opened, atol=1e-12)


@pytest.mark.parametrize("substeps", [1, 3])
def test_joint_acceleration_is_the_velocity_difference_over_the_last_physics_step(substeps):
    physics = PhysicsCfg(substeps=substeps)
    env = MobileManiEnv(EnvCfg(num_envs=2, seed=3, physics=physics, task=TaskCfg(object="test/box")))
    env.reset()
    assert np.all(env.frames.joint_acc == 0.0)  # after a reset, as the reference's zeroed history
    rng = np.random.default_rng(0)
    active = env.frame_reader.active_dof
    for _ in range(5):
        actions = rng.uniform(-1, 1, (2, env.num_actions))
        # Replay the step's physics on one MjData per env: substeps - 1 steps, then the last one.
        replicas = []
        for e in range(2):
            data = mujoco.MjData(env.model)
            data.qpos[:], data.qvel[:] = env.view.qpos[e], env.view.qvel[e]
            data.mocap_pos[:], data.mocap_quat[:] = env.view.mocap_pos[e], env.view.mocap_quat[e]
            replicas.append(data)
        previous = env.frames.joint_vel.copy()
        env.step(actions)
        for e, data in enumerate(replicas):
            data.ctrl[:] = env.view.ctrl[e]
            for _ in range(substeps - 1):
                mujoco.mj_step(env.model, data)
            before_last = data.qvel[active].copy()
            mujoco.mj_step(env.model, data)
            expected = (data.qvel[active] - before_last) / physics.timestep
            np.testing.assert_allclose(env.frames.joint_acc[e], expected, rtol=1e-3, atol=1e-3)
        if substeps == 1:  # the last substep is the whole control step
            expected = (env.frames.joint_vel - previous) / physics.timestep
            np.testing.assert_allclose(env.frames.joint_acc, expected, rtol=1e-9, atol=1e-9)


def _hand_contacts(spec: mujoco.MjSpec, samples: int) -> int:
    """Robot-robot contacts over random joint configurations of the robot alone."""
    model = spec.compile()
    data = mujoco.MjData(model)
    rng = np.random.default_rng(0)
    count = 0
    for _ in range(samples):
        for j in range(model.njnt):
            if model.jnt_limited[j]:
                data.qpos[model.jnt_qposadr[j]] = rng.uniform(*model.jnt_range[j])
        mujoco.mj_forward(model, data)
        count += data.ncon
    return count


def test_xhand_fingers_collide_with_each_other_and_g1_never_with_itself():
    xhand = build_xhand_spec().compile()
    hand_geoms = [g for g in range(xhand.ngeom) if xhand.geom_contype[g] & HAND_BIT]
    assert len(hand_geoms) == 11  # palm + 2 phalanges x 5 digits
    pairs = [
        (a, b)
        for a, b in itertools.combinations(hand_geoms, 2)
        if xhand.geom_contype[a] & xhand.geom_conaffinity[b]
        or xhand.geom_contype[b] & xhand.geom_conaffinity[a]
    ]
    assert len(pairs) == len(hand_geoms) * (len(hand_geoms) - 1) // 2
    # Random finger configurations bring fingers into contact; the G1 robot alone never touches itself.
    assert _hand_contacts(build_xhand_spec(), 200) > 0
    assert _hand_contacts(build_g1_spec(), 200) == 0

"""Differential IK tracking, whole-body base motion, and reset sampling ranges."""

import numpy as np
import pytest

from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.utils.rotations import (
    axis_angle_from_quat,
    euler_from_quat,
    quat_conj,
    quat_from_euler,
    quat_mul,
)


def _hand_pose(env):
    return env.frames.hand_pos.copy(), env.frames.hand_quat.copy()


@pytest.mark.parametrize("robot", ["g1", "xhand"])
def test_ik_reaches_wrist_target_within_1cm_3deg_in_60_steps(robot):
    env = MobileManiEnv(EnvCfg(num_envs=4, seed=3, task=TaskCfg(robot=robot)))
    env.reset()
    start_pos, start_quat = _hand_pose(env)
    # Away from the object (in front of the robot), so only kinematics and control are tested.
    offsets = np.array([[0.15, 0.05, 0.10], [-0.15, 0.0, 0.05], [0.05, -0.10, 0.15], [0.0, -0.15, 0.12]])
    turns = quat_from_euler(np.array([[0.0, 0.0, 0.3], [0.2, 0.0, 0.0], [0.0, 0.25, 0.0], [-0.2, 0.1, -0.2]]))
    target_pos, target_quat = start_pos + offsets, quat_mul(turns, start_quat)
    for _ in range(60):
        pos, quat = _hand_pose(env)
        actions = np.zeros((4, env.num_actions))
        actions[:, 0:3] = np.clip((target_pos - pos) / 0.025, -1, 1)
        actions[:, 3:6] = np.clip(euler_from_quat(quat_mul(target_quat, quat_conj(quat))) / 0.025, -1, 1)
        actions[:, 6:] = env.default_hand_action
        env.step(actions)
    pos, quat = _hand_pose(env)
    position_error = np.linalg.norm(target_pos - pos, axis=1)
    angle_error = np.degrees(
        np.linalg.norm(axis_angle_from_quat(quat_mul(target_quat, quat_conj(quat))), axis=1)
    )
    assert position_error.max() < 0.01, position_error
    assert angle_error.max() < 3.0, angle_error


def test_base_joints_move_through_ik_alone():
    env = MobileManiEnv(EnvCfg(num_envs=2, seed=0))
    env.reset()
    idx = env.index
    base_start = env.view.qpos[:, idx.ik_qpos[:2]].copy()
    # Far forward (env 0) and far to the side (env 1): beyond the arm's reach, so the base must move.
    actions = np.zeros((2, 7))
    actions[0, 1] = 1.0
    actions[1, 0] = 1.0
    actions[:, 6] = 1.0
    for _ in range(40):
        env.step(actions)
    base_moved = env.view.qpos[:, idx.ik_qpos[:2]] - base_start
    assert base_moved[0, 1] > 0.2  # slider_basey: forward slide
    assert abs(base_moved[1, 0]) > 0.2  # slider_basex: yaw
    assert env.robot.action_dim == 7  # no separate base action


def _yaw_of(quat):
    return euler_from_quat(quat)[:, 2]


def test_reset_ranges_open_tabletop():
    env = MobileManiEnv(EnvCfg(num_envs=256, seed=5))
    env.reset()
    idx, v = env.index, env.view
    root_xy = v.mocap_pos[:, idx.robot_mocap, :2]
    assert np.all(root_xy[:, 0] >= -0.25) and np.all(root_xy[:, 0] <= 0.25)
    assert np.all(root_xy[:, 1] >= -1.5) and np.all(root_xy[:, 1] <= -1.0)
    facing = np.arctan2(root_xy[:, 0], -root_xy[:, 1])
    jitter = np.degrees(_yaw_of(v.mocap_quat[:, idx.robot_mocap]) - facing)
    assert np.abs(jitter).max() <= 15.0 + 1e-6 and np.abs(jitter).max() > 10.0
    # Grasp point over the env origin; stage top at init height 0.2 + U(0, 0.5).
    np.testing.assert_allclose(env.frames.grasp_pos[:, :2], 0.0, atol=1e-9)
    stage_top = v.mocap_pos[:, idx.stage_mocap, 2] + 0.5
    assert stage_top.min() >= 0.2 and stage_top.max() <= 0.7 and np.ptp(stage_top) > 0.4
    assert np.all(env.view.qpos[:, idx.robot_qpos] == idx.robot_default_qpos)
    np.testing.assert_allclose(v.qpos[:, idx.object_joint_qpos], np.radians(10.0))  # box starts 10° open
    assert np.all(env.env_times == 0) and np.all(env.last_action == 0)


def test_reset_ranges_close_and_pick():
    close = MobileManiEnv(EnvCfg(num_envs=256, seed=2, task=TaskCfg(skill="close")))
    close.reset()
    angles = np.degrees(close.view.qpos[:, close.index.object_joint_qpos])
    assert angles.min() >= 40.0 and angles.max() <= 80.0 and np.ptp(angles) > 30
    pick = MobileManiEnv(EnvCfg(num_envs=256, seed=2, task=TaskCfg(object="test/can", skill="pick")))
    pick.reset()
    q = pick.index.object_free_qpos
    yaw = np.degrees(_yaw_of(pick.view.qpos[:, q + 3 : q + 7]))
    assert np.abs(yaw).max() <= 90.0 and np.ptp(yaw) > 120
    np.testing.assert_allclose(pick.view.qpos[:, q + 1], 0.1)  # constant +0.1 m y offset
    np.testing.assert_allclose(
        pick.goal_pos - pick.frames.grasp_pos, np.tile([0, 0, 0.2], (256, 1)), atol=2e-3
    )

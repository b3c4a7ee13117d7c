"""The fixed-base option (the paper's Table 8 ablation, `env=fixed_base`): the base's joints stay exactly at
their reset values while the arm reaches, the robot starts 0.5-1.0 m in front of the grasp point, and without
the option the base moves as before."""

import dataclasses

import numpy as np
import pytest
from roots import compose_root

from mobilemani_rl.envs.config import EnvCfg, ResetCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.rl.config import RLCfg
from mobilemani_rl.scripted.policy import ScriptedPolicy
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.errors import InputError


def _preset(robot: str, num_envs: int, seed: int) -> EnvCfg:
    """The env of `env=fixed_base`, as the RL entry point composes it."""
    cfg = to_dataclass(compose_root("rl", ["env=fixed_base", f"robot={robot}"]), RLCfg).env_cfg()
    return dataclasses.replace(cfg, num_envs=num_envs, seed=seed)


def _scripted_episode(env: MobileManiEnv, steps: int) -> dict[str, np.ndarray]:
    """Base and arm joint positions and palm-to-grasp distances, after the reset and after every step."""
    env.reset()
    policy, idx = ScriptedPolicy(env), env.index
    arm_qpos = idx.ik_qpos[~idx.ik_is_base]
    base, arm, hand = [], [], []
    for step in range(steps + 1):
        if step:
            assert env.step(policy()).done_ids.size == 0  # one episode, no reset in between
        base.append(env.view.qpos[:, env.base_qpos].copy())
        arm.append(env.view.qpos[:, arm_qpos].copy())
        hand.append(env.task_distances.hand.copy())
    return {"base": np.array(base), "arm": np.array(arm), "hand": np.array(hand)}


@pytest.mark.parametrize("robot", ["g1", "xhand"])
def test_fixed_base_keeps_the_base_joints_still_while_the_arm_reaches(robot):
    env = MobileManiEnv(_preset(robot, num_envs=4, seed=1))
    episode = _scripted_episode(env, steps=100)
    # exactly the reset values (the robot's defaults) at every step, velocity zero
    assert np.array_equal(episode["base"], np.broadcast_to(env.base_value, episode["base"].shape))
    assert np.all(env.view.qvel[:, env.base_dof] == 0.0)
    assert np.all(np.abs(episode["arm"] - episode["arm"][0]).max(axis=(0, 2)) > 0.1)
    start, closest = episode["hand"][0], episode["hand"].min(axis=0)
    assert np.all(closest < start - 0.05), (start, closest)


def test_without_the_option_the_same_start_moves_the_base():
    fixed = _preset("g1", num_envs=4, seed=1)
    episode = _scripted_episode(MobileManiEnv(dataclasses.replace(fixed, fixed_base=False)), steps=100)
    moved = np.abs(episode["base"] - episode["base"][0]).max(axis=(0, 2))
    assert np.all(moved > 1e-3), moved
    assert EnvCfg().fixed_base is False and EnvCfg().reset.root_y_distance_range is None


@pytest.mark.parametrize("robot", ["g1", "xhand"])
def test_fixed_base_starts_half_a_metre_to_a_metre_in_front_of_the_grasp_point(robot):
    env = MobileManiEnv(_preset(robot, num_envs=256, seed=5))
    env.reset()
    idx, v = env.index, env.view
    root = v.mocap_pos[:, idx.robot_mocap, :2] - env.frames.grasp_pos[:, :2]
    assert root[:, 0].min() >= -0.25 and root[:, 0].max() <= 0.25 and np.ptp(root[:, 0]) > 0.4
    assert root[:, 1].min() >= -1.0 and root[:, 1].max() <= -0.5 and np.ptp(root[:, 1]) > 0.4
    assert np.all(v.qpos[:, idx.robot_qpos] == idx.robot_default_qpos)


def test_a_start_inside_the_stage_or_an_ignored_range_is_named():
    inside = EnvCfg(fixed_base=True, reset=ResetCfg(root_y_distance_range=[0.2, 1.0]), task=TaskCfg())
    with pytest.raises(InputError, match=r"env.reset.root_y_distance_range=\[0.2, 1.0\] .* inside the stage"):
        MobileManiEnv(inside)
    both = EnvCfg(reset=ResetCfg(root_y_range=[0.2, 0.4], root_y_distance_range=[0.5, 1.0]))
    with pytest.raises(InputError, match=r"env.reset.root_y_range=\[0.2, 0.4\] has no effect"):
        MobileManiEnv(both)

"""The env's faster numpy paths give numpy's own results bit for bit, so speed-ups leave rollouts alone."""

import numpy as np
import pytest

from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.observations import compute_observation, normalize_to_limits, time_encoding
from mobilemani_rl.utils.rotations import euler_from_quat, mean_last, sum_last, vector_norm


@pytest.mark.parametrize("leading", [(5,), (7, 4), (2, 3, 2)])
@pytest.mark.parametrize("length", [1, 2, 3, 4, 6, 7, 8, 12])
def test_sums_and_means_over_the_last_axis_equal_numpys_bit_for_bit(leading, length):
    values = np.random.default_rng(length).standard_normal((*leading, length)) * 10.0 ** np.arange(length)
    assert np.array_equal(sum_last(values), np.sum(values, axis=-1))
    assert np.array_equal(sum_last(values, keepdims=True), np.sum(values, axis=-1, keepdims=True))
    assert np.array_equal(mean_last(values), np.mean(values, axis=-1))
    assert np.array_equal(vector_norm(values), np.sqrt(np.sum(values * values, axis=-1)))


def concatenated_observation(frames, distances, steps, last_action, goal_pos, limits, clip):
    """The observation built by plain concatenation in float64, as the layout in docs/reference.md reads."""
    n, fingers = frames.finger_pos.shape[:2]
    euler = euler_from_quat(
        np.concatenate((frames.palm_quat[:, None], frames.finger_quat, frames.grasp_quat[:, None]), axis=1)
    )
    finger_block = np.concatenate(
        (frames.finger_pos, euler[:, 1:-1], frames.finger_linvel, frames.finger_angvel), axis=2
    )
    joints = np.stack(
        (normalize_to_limits(frames.joint_pos, limits), frames.joint_vel, frames.joint_acc), axis=2
    )
    grasp = frames.grasp_pos
    obs = np.concatenate(
        (
            time_encoding(steps),
            last_action,
            frames.palm_pos,
            euler[:, 0],
            frames.palm_linvel,
            frames.palm_angvel,
            finger_block.reshape(n, -1),
            joints.reshape(n, -1),
            distances.hand[:, None],
            distances.finger,
            distances.body,
            grasp - frames.palm_pos,
            grasp,
            euler[:, -1],
            goal_pos - grasp,
        ),
        axis=1,
    )
    obs = np.clip(obs, -clip, clip)
    obs[np.isnan(obs)] = 0.0
    return obs.astype(np.float32)


def test_the_observation_equals_its_concatenated_layout_bit_for_bit_with_clipped_and_nan_entries():
    env = MobileManiEnv(EnvCfg(num_envs=4, task=TaskCfg(robot="g1", object="test/box", skill="open")))
    env.reset(seed=3)
    env.step(np.random.default_rng(0).uniform(-1, 1, (4, env.num_actions)))
    frames, distances = env.frames, env.task_distances
    frames.joint_vel[0, 0], frames.joint_acc[1, 2], frames.palm_linvel[2, 1] = 1e9, np.nan, -np.inf
    args = (frames, distances, env.env_times, env.last_action, env.goal_pos, env.joint_limits, 0.3)
    observed = compute_observation(*args)
    assert observed.dtype == np.float32
    assert np.array_equal(observed, concatenated_observation(*args))
    assert np.abs(observed).max() == np.float32(0.3) and not np.isnan(observed).any()

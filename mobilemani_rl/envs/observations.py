"""The policy observation in the reference order (docs/reference.md, "Observation"): 146-d G1, 223-d XHand."""

from __future__ import annotations

import numpy as np

from mobilemani_rl.envs.frames import Frames
from mobilemani_rl.envs.rewards import TaskDistances
from mobilemani_rl.utils.rotations import euler_from_quat

TIME_ENCODING_DIM = 30
# f_i = exp(-2i·ln(10000)/30), i = 0..14: slot 2i = sin(t·f_i), slot 2i+1 = cos(t·f_i), t in control steps.
_FREQUENCIES = np.exp(-2.0 * np.arange(TIME_ENCODING_DIM // 2) * np.log(10000.0) / TIME_ENCODING_DIM)


def _encode_time(steps: np.ndarray) -> np.ndarray:
    angles = steps[:, None].astype(np.float64) * _FREQUENCIES
    encoding = np.empty((steps.shape[0], TIME_ENCODING_DIM))
    encoding[:, 0::2] = np.sin(angles)
    encoding[:, 1::2] = np.cos(angles)
    return encoding


# Episodes count control steps from 0, so per-step encodings come from a table (the trig costs more than the
# lookup); steps past it, as in long evaluations, are computed.
_TIME_TABLE = _encode_time(np.arange(1024))


def time_encoding(steps: np.ndarray) -> np.ndarray:
    if steps.size and steps.max() < len(_TIME_TABLE):
        return _TIME_TABLE[steps]
    return _encode_time(steps)


def observation_dim(num_actions: int, num_fingers: int, num_bodies: int, num_joints: int) -> int:
    return (
        TIME_ENCODING_DIM
        + num_actions
        + 12
        + 12 * num_fingers
        + 3 * num_joints
        + (1 + num_fingers + num_bodies + 3)
        + 9
    )


def normalize_to_limits(values: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """Map joint values onto [-1, 1] by their (J, 2) limits."""
    low, high = limits[:, 0], limits[:, 1]
    return 2.0 * (values - low) / (high - low) - 1.0


def compute_observation(
    frames: Frames,
    distances: TaskDistances,
    steps: np.ndarray,
    last_action: np.ndarray,
    goal_pos: np.ndarray,
    joint_limits: np.ndarray,
    clip: float,
) -> np.ndarray:
    n, num_fingers = frames.finger_pos.shape[:2]
    # One Euler conversion for palm, fingers and object link: fewer small numpy calls per step.
    euler = euler_from_quat(
        np.concatenate((frames.palm_quat[:, None], frames.finger_quat, frames.grasp_quat[:, None]), axis=1)
    )
    palm = np.concatenate((frames.palm_pos, euler[:, 0], frames.palm_linvel, frames.palm_angvel), axis=1)
    fingers = np.concatenate(
        (frames.finger_pos, euler[:, 1:-1], frames.finger_linvel, frames.finger_angvel), axis=2
    ).reshape(n, 12 * num_fingers)
    joints = np.stack(
        (normalize_to_limits(frames.joint_pos, joint_limits), frames.joint_vel, frames.joint_acc), axis=2
    ).reshape(n, 3 * frames.joint_pos.shape[1])
    grasp = frames.grasp_pos
    robot_object = np.concatenate(
        (distances.hand[:, None], distances.finger, distances.body, grasp - frames.palm_pos), axis=1
    )
    obj = np.concatenate((grasp, euler[:, -1], goal_pos - grasp), axis=1)
    obs = np.concatenate(
        (time_encoding(steps), last_action, palm, fingers, joints, robot_object, obj), axis=1
    )
    np.clip(obs, -clip, clip, out=obs)  # ±inf become ±clip
    obs[np.isnan(obs)] = 0.0
    return obs.astype(np.float32)

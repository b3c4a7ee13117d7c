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


class _ColumnWriter:
    """Fills an observation buffer block by block, left to right, so that no block is first concatenated
    into a float64 copy. Assigning casts to float32, and rounding is monotonic, so clipping afterwards in
    float32 gives the same values as clipping in float64 and casting."""

    def __init__(self, out: np.ndarray) -> None:
        self.out, self.column = out, 0

    def add(self, *blocks: np.ndarray) -> None:
        """(n, w) blocks, one after another."""
        for block in blocks:
            width = block.shape[1]
            self.out[:, self.column : self.column + width] = block
            self.column += width

    def add_interleaved(self, *parts: np.ndarray) -> None:
        """Parts (n, k, w_i) or (n, k) of k items, written item after item, each item's parts in order
        (as concatenating them on their last axis and flattening would)."""
        parts = tuple(p[..., None] if p.ndim == 2 else p for p in parts)
        n, items = parts[0].shape[:2]
        width = sum(p.shape[2] for p in parts)
        # splitting the row's slice into (items, width) is always a view: the writes reach the buffer
        view = self.out[:, self.column : self.column + items * width].reshape(n, items, width)
        offset = 0
        for p in parts:
            view[:, :, offset : offset + p.shape[2]] = p
            offset += p.shape[2]
        self.column += items * width


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
    num_joints = frames.joint_pos.shape[1]
    # One Euler conversion for palm, fingers and object link: fewer small numpy calls per step.
    euler = euler_from_quat(
        np.concatenate((frames.palm_quat[:, None], frames.finger_quat, frames.grasp_quat[:, None]), axis=1)
    )
    dim = observation_dim(last_action.shape[1], num_fingers, distances.body.shape[1], num_joints)
    obs = np.empty((n, dim), np.float32)
    columns = _ColumnWriter(obs)
    grasp = frames.grasp_pos
    columns.add(time_encoding(steps), last_action)
    columns.add(frames.palm_pos, euler[:, 0], frames.palm_linvel, frames.palm_angvel)
    columns.add_interleaved(frames.finger_pos, euler[:, 1:-1], frames.finger_linvel, frames.finger_angvel)
    columns.add_interleaved(
        normalize_to_limits(frames.joint_pos, joint_limits), frames.joint_vel, frames.joint_acc
    )
    columns.add(distances.hand[:, None], distances.finger, distances.body, grasp - frames.palm_pos)
    columns.add(grasp, euler[:, -1], goal_pos - grasp)
    np.clip(obs, -clip, clip, out=obs)  # ±inf become ±clip
    np.copyto(obs, 0.0, where=np.isnan(obs))
    return obs

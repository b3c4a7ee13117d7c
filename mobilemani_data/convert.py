"""One recorded episode -> the schema's per-frame vectors and images (mobilemani_data.schema).

Exported frames are the recorded states t = 1 … T-1 (the reset state is dropped, as in the reference).
The action stored with frame t is the one the teacher took after seeing it (applied from state t): the
reference's label shift by one happens here, so a reader takes `action` / `world.action` of a frame as
its label as they are.
"""

from __future__ import annotations

import numpy as np

from mobilemani_data import schema
from mobilemani_data.frame import FrameState, frame_images, frame_vectors
from mobilemani_data.replay import Replayer
from mobilemani_data.shards import Episode
from mobilemani_rl.envs.base_frame import Convention, action_to_base
from mobilemani_rl.render import CameraRenderer

FIRST_FRAME = 1  # state 0 is the reset


def episode_frame_state(episode: Episode, num_hand_joints: int) -> FrameState:
    """The frame builder's inputs for frames 1 … T-1 of a recorded episode."""
    a = {k: v[FIRST_FRAME:] for k, v in episode.arrays.items() if k != "goal_pos"}
    n = len(a["state"])
    return FrameState(
        a["hand_pos"],
        a["hand_quat"],
        a["base_pos"],
        a["base_quat"],
        a["joint_pos"][:, -num_hand_joints:],
        np.broadcast_to(episode.arrays["grasp_pos"][0], (n, 3)),
        np.broadcast_to(episode.arrays["goal_pos"], (n, 3)),
    )


def smoothed_labels(actions: np.ndarray, window: int) -> np.ndarray:
    """(T, A) actions averaged over a centred window of `window` control steps (odd; 1: unchanged), the ends
    padded with their edge values. A PPO teacher's action holds fast reactions to what a VLA never observes
    (its clock, joint velocities, the DART noise it just received: docs/results/teacher_labels.md); over a
    few steps they average out, while the motion, whose wrist deltas add up, keeps its course."""
    if window <= 1:
        return actions
    half = window // 2
    padded = np.pad(actions, ((half, half), (0, 0)), mode="edge")
    return np.lib.stride_tricks.sliding_window_view(padded, window, axis=0).mean(axis=-1)


def episode_vectors(
    episode: Episode, num_hand_joints: int, convention: Convention, label_window: int = 1
) -> dict[str, np.ndarray]:
    """Every non-image feature for frames 1 … T-1, float32; the action labels smoothed over
    `label_window` steps (`smoothed_labels`)."""
    frames = episode_frame_state(episode, num_hand_joints)
    action = smoothed_labels(episode.arrays["action"], label_window)[FIRST_FRAME:]
    vectors = frame_vectors(frames)
    vectors[schema.WORLD_ACTION] = action.astype(np.float32)
    vectors[schema.ACTION] = action_to_base(action, frames.base_quat, convention).astype(np.float32)
    return vectors


def camera_images(
    renderer: CameraRenderer,
    replayer: Replayer,
    state: np.ndarray,
    cameras: dict[str, str],
    keys: list[str] | None = None,
) -> dict[str, np.ndarray]:
    """Render one recorded state: {feature name: (H, W, 3) uint8} for the image features `keys`
    (default: every modality of every camera). `cameras` maps the schema's camera names
    (head, wrist) to the robot's MuJoCo ones.
    """
    return frame_images(renderer.render(replayer.set_state(state)), cameras, keys)

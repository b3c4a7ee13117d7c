"""The one frame builder: simulator quantities (+ rendered cameras)
-> the dataset's feature vectors and images.

The exporter (recorded episodes) and the closed-loop observer (live envs) both call these functions, so what a
policy is trained on and what it sees in evaluation are the same function of the simulator state.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from mobilemani_data import schema
from mobilemani_rl.assets.robots import RobotDescription
from mobilemani_rl.envs.base_frame import points_to_base
from mobilemani_rl.render import CameraFrame
from mobilemani_rl.utils.rotations import euler_from_quat, quat_apply, quat_conj, quat_mul


@dataclass
class FrameState:
    """World-frame quantities of n frames, each (n, ...): the robot's hand and base poses, its hand joints,
    the episode's grasp point at reset and its goal point."""

    hand_pos: np.ndarray
    hand_quat: np.ndarray
    base_pos: np.ndarray
    base_quat: np.ndarray
    hand_joint_pos: np.ndarray
    grasp0: np.ndarray
    goal: np.ndarray


def world_state(s: FrameState) -> np.ndarray:
    """`world.state` rows: hand pos, hand RPY, base pos, base RPY, hand joints (all world frame)."""
    return np.concatenate(
        (
            s.hand_pos,
            euler_from_quat(s.hand_quat),
            s.base_pos,
            euler_from_quat(s.base_quat),
            s.hand_joint_pos,
        ),
        axis=-1,
    )


def rotation_6d(quat: np.ndarray) -> np.ndarray:
    """Unit quaternions (n, 4) -> the first two columns of their rotation matrices (n, 6): continuous
    everywhere, unlike Euler angles, whose roll wraps at ±π for a palm turned over
    (Zhou et al., CVPR 2019)."""
    x_axis = quat_apply(quat, np.broadcast_to([1.0, 0.0, 0.0], quat.shape[:-1] + (3,)))
    y_axis = quat_apply(quat, np.broadcast_to([0.0, 1.0, 0.0], quat.shape[:-1] + (3,)))
    return np.concatenate((x_axis, y_axis), axis=-1)


def wrist_pose_base(s: FrameState) -> np.ndarray:
    """The hand's pose in the base frame: position (3) + 6D rotation (6)."""
    local = quat_mul(quat_conj(s.base_quat), s.hand_quat)
    return np.concatenate((points_to_base(s.hand_pos, s.base_pos, s.base_quat), rotation_6d(local)), axis=-1)


def frame_vectors(s: FrameState) -> dict[str, np.ndarray]:
    """Every observation vector of the schema, float32 (n, d). The grasp point at reset and the goal are fixed
    in the world; the base moves, so each frame sees them anew in its own base frame."""
    vectors = {
        schema.STATE: np.concatenate((wrist_pose_base(s), s.hand_joint_pos), axis=-1),
        schema.WORLD_STATE: world_state(s),
        schema.GRASP_POINT_BASE: points_to_base(s.grasp0, s.base_pos, s.base_quat),
        schema.GOAL_POINT_BASE: points_to_base(s.goal, s.base_pos, s.base_quat),
    }
    return {k: v.astype(np.float32) for k, v in vectors.items()}


def robot_cameras(robot: RobotDescription) -> dict[str, str]:
    """Schema camera name (head, wrist) -> the robot's MuJoCo camera."""
    return dict(zip(schema.CAMERAS, (robot.head_camera, robot.wrist_camera), strict=True))


def modality_image(frame: CameraFrame, modality: str) -> np.ndarray:
    """One camera's rendering as a 3-channel (H, W, 3) uint8 image: RGB, depth (0–5 m as 0–255) or
    segmentation (label x SEGMENTATION_SCALE), single channels replicated."""
    if modality == "rgb":
        return frame.rgb
    if modality == "depth":
        channel = frame.depth_image
    elif modality == "seg":
        channel = (frame.segmentation * schema.SEGMENTATION_SCALE).astype(np.uint8)
    else:
        raise KeyError(f"unknown modality {modality!r}; valid: {list(schema.MODALITIES)}")
    return np.repeat(channel[..., None], 3, axis=2)


def frame_images(
    rendered: Mapping[str, CameraFrame], cameras: Mapping[str, str], keys: Iterable[str] | None = None
) -> dict[str, np.ndarray]:
    """Rendered MuJoCo cameras -> {feature name: (H, W, 3) uint8}. `cameras` maps the schema's camera names
    (head, wrist) to the robot's MuJoCo camera names; `keys` limits the output to those feature names
    (default: every modality of every camera in `cameras`)."""
    wanted = set(keys) if keys is not None else None
    images = {}
    for camera, mj_camera in cameras.items():
        for modality in schema.MODALITIES:
            key = schema.image_key(camera, modality)
            if wanted is None or key in wanted:
                images[key] = modality_image(rendered[mj_camera], modality)
    return images

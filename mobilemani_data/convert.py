"""One recorded episode -> the schema's per-frame vectors and images (mobilemani_data.schema).

Exported frames are the recorded states t = 1 … T-1 (the reset state is dropped as in reference §8d). The action
stored with frame t is the one the teacher took after seeing it (applied from state t): the label shift of
reference §8g happens here, so a reader takes `action` / `action_base` of a frame as its label as they are.
"""

from __future__ import annotations

import numpy as np

from mobilemani_data import schema
from mobilemani_data.replay import Replayer
from mobilemani_data.shards import Episode
from mobilemani_rl.base_frame import Convention, action_to_base, points_to_base, pose_to_base
from mobilemani_rl.render import CameraRenderer

FIRST_FRAME = 1  # state 0 is the reset


def episode_vectors(episode: Episode, num_hand_joints: int, convention: Convention) -> dict[str, np.ndarray]:
    """Every non-image feature for frames 1 … T-1, float32."""
    a = {k: v[FIRST_FRAME:] for k, v in episode.arrays.items() if k != "goal_pos"}
    n = len(a["state"])
    base_pos, base_quat = a["base_pos"], a["base_quat"]
    state = schema.world_state(a["hand_pos"], a["hand_quat"], base_pos, base_quat, a["joint_pos"][:, -num_hand_joints:])
    # The initial grasp point and the goal are fixed in the world; the base moves, so each frame sees them anew.
    grasp0 = np.broadcast_to(episode.arrays["grasp_pos"][0], (n, 3))
    goal = np.broadcast_to(episode.arrays["goal_pos"], (n, 3))
    vectors = {
        schema.STATE: state,
        schema.WRIST_POSE_BASE: pose_to_base(a["hand_pos"], a["hand_quat"], base_pos, base_quat),
        schema.GRASP_POINT_BASE: points_to_base(grasp0, base_pos, base_quat),
        schema.GOAL_POINT_BASE: points_to_base(goal, base_pos, base_quat),
        schema.ACTION: a["action"],
        schema.ACTION_BASE: action_to_base(a["action"], base_quat, convention),
    }
    return {k: v.astype(np.float32) for k, v in vectors.items()}


def camera_images(renderer: CameraRenderer, replayer: Replayer, state: np.ndarray,
                  cameras: dict[str, str]) -> dict[str, np.ndarray]:
    """Render one recorded state: {feature name: (H, W, 3) uint8} for each schema camera and modality.

    `cameras` maps the schema's camera names (head, wrist) to the robot's MuJoCo camera names.
    """
    rendered = renderer.render(replayer.set_state(state))
    images = {}
    for name, mj_camera in cameras.items():
        frame = rendered[mj_camera]
        images[schema.image_key(name, "rgb")] = frame.rgb
        images[schema.image_key(name, "depth")] = np.repeat(frame.depth_image[..., None], 3, axis=2)
        seg = (frame.segmentation * schema.SEGMENTATION_SCALE).astype(np.uint8)
        images[schema.image_key(name, "seg")] = np.repeat(seg[..., None], 3, axis=2)
    return images

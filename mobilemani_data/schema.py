"""The LeRobot dataset schema shared by the exporter (mobilemani_data) and the VLA reader (mobilemani_vla).

Feature names, shapes and meanings. Images are stored as videos (H, W, 3) uint8; depth is the ray distance
clipped to 0–5 m and scaled to 0–255, replicated to 3 channels; segmentation is object = 1, robot = 2,
background = 0, scaled by SEGMENTATION_SCALE so the classes survive lossy video.
"""

from __future__ import annotations

FPS = 30
CAMERAS = ("head", "wrist")
MODALITIES = ("rgb", "depth", "seg")
DEPTH_RANGE_M = 5.0
SEGMENTATION_SCALE = 100  # label * 100 in every channel: 0, 100, 200

STATE = "observation.state"  # world: hand pos (3), hand RPY (3), base pos (3), base RPY (3), hand joints (nh)
WRIST_POSE_BASE = "observation.wrist_pose_base"  # hand pos + RPY in the base frame (6)
GRASP_POINT_BASE = "observation.grasp_point_base"  # first frame's grasp point in the base frame (3)
GOAL_POINT_BASE = "observation.goal_point_base"  # first frame's goal point in the base frame (3)
ACTION = "action"  # world-frame normalised action as applied (7 g1 / 18 xhand)
ACTION_BASE = "action_base"  # the same action in the base frame (mobilemani_rl.base_frame)

EPISODE_METADATA = ("robot", "object_id", "category", "skill", "scene", "split", "seed")


def image_key(camera: str, modality: str) -> str:
    return f"observation.images.{camera}_{modality}"


def state_dim(num_hand_joints: int) -> int:
    return 12 + num_hand_joints


def features(action_dim: int, num_hand_joints: int, height: int, width: int,
             cameras: tuple[str, ...] = CAMERAS, modalities: tuple[str, ...] = MODALITIES) -> dict[str, dict]:
    """The `features` argument of `LeRobotDataset.create` for one robot."""
    image = {"dtype": "video", "shape": (height, width, 3), "names": ["height", "width", "channels"]}
    vector = lambda n: {"dtype": "float32", "shape": (n,), "names": None}  # noqa: E731
    spec = {image_key(c, m): dict(image) for c in cameras for m in modalities}
    spec.update({
        STATE: vector(state_dim(num_hand_joints)),
        WRIST_POSE_BASE: vector(6),
        GRASP_POINT_BASE: vector(3),
        GOAL_POINT_BASE: vector(3),
        ACTION: vector(action_dim),
        ACTION_BASE: vector(action_dim),
    })
    return spec

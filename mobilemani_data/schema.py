"""The LeRobot dataset schema shared by the exporter (mobilemani_data) and the VLA reader (mobilemani_vla).

Feature names, shapes and meanings. Images are stored as videos (H, W, 3) uint8; depth is the ray distance
clipped to 0–5 m and scaled to 0–255, replicated to 3 channels; segmentation is object = 1, robot = 2,
background = 0, scaled by SEGMENTATION_SCALE so the classes survive lossy video.

Frames are the recorded control steps t = 1 … T-1 of an episode (as in the reference: neither the reset nor
the terminal state). Action labels are aligned at export (the reference's shift by one): `action` /
`world.action` of frame t is the action the teacher took after seeing frame t (applied from state t, leading
to t+1), so a reader uses them as they are; the last frame's label is the episode's final action (no
duplication needed).
"""

from __future__ import annotations

FPS = 30
CAMERAS = ("head", "wrist")
MODALITIES = ("rgb", "depth", "seg")
SEGMENTATION_SCALE = 100  # label * 100 in every channel: 0, 100, 200
# Image stream names, camera_modality: head_rgb, head_depth, head_seg, wrist_rgb, ...
IMAGE_STREAMS = tuple(f"{camera}_{modality}" for camera in CAMERAS for modality in MODALITIES)

# LeRobot's conventions (lerobot.utils.feature_utils.dataset_to_policy_features): every feature named
# "action*" is an output and only `action` is loaded in chunks; "observation.state" is the state stock
# policies read; "observation.images.*" are their image inputs. So the policy-facing features are exactly
# these, and every extra signal is named outside the "action" / "observation" prefixes,
# where LeRobot policies ignore it.
STATE = "observation.state"  # proprioception, base frame: wrist pos (3) + 6D rotation (6), hand joints (nh)
WRIST_POSE_DIM = 9  # observation.state[:9]: the wrist pose in the base frame (the paper's VLA state input)
# The action in the frame's base frame (mobilemani_rl.envs.base_frame), [-1, 1] (7 g1 / 18 xhand). Base, not
# world: a policy sees onboard cameras and base-frame proprioception only, so a world-frame action would ask
# it to infer the base's heading in the world, which none of its inputs carries (the paper's VLA predicts
# base-frame actions).
ACTION = "action"
# Extras, not policy inputs by default:
WORLD_STATE = (
    "world.state"  # world frame: hand pos (3), hand RPY (3), base pos (3), base RPY (3), hand joints (nh)
)
WORLD_ACTION = "world.action"  # the env's normalised world-frame action as applied, clamped to [-1, 1]
# The episode's initial (reset-state) grasp point and its goal point: fixed world points, expressed in each
# frame's current base frame (the base moves during the episode);
# the paper's "pseudo-observations" for the VLA ablation.
GRASP_POINT_BASE = "object.grasp_point_base"  # (3)
GOAL_POINT_BASE = "object.goal_point_base"  # (3)

EPISODE_METADATA = ("robot", "object_id", "category", "skill", "scene", "split", "seed")
# One JSON line per episode_index with EPISODE_METADATA plus scene_split, instruction, teacher, length, and
# the raw shard it came from; written by mobilemani_data.export next to LeRobot's own metadata.
EPISODES_FILE = "meta/mobilemani_episodes.jsonl"
EXPORT_REPORT_FILE = "meta/mobilemani_export.json"  # image size, codec, action convention, skipped shards
STATS_FILE = "meta/mobilemani_stats.json"  # mobilemani_data.stats' report, rewritten by every `make data`


def image_key(camera: str, modality: str) -> str:
    return f"observation.images.{camera}_{modality}"


def state_dim(num_hand_joints: int) -> int:
    return WRIST_POSE_DIM + num_hand_joints


def world_state_dim(num_hand_joints: int) -> int:
    return 12 + num_hand_joints


def features(
    action_dim: int,
    num_hand_joints: int,
    height: int,
    width: int,
    cameras: tuple[str, ...] = CAMERAS,
    modalities: tuple[str, ...] = MODALITIES,
) -> dict[str, dict]:
    """The `features` argument of `LeRobotDataset.create` for one robot."""
    image = {"dtype": "video", "shape": (height, width, 3), "names": ["height", "width", "channels"]}
    vector = lambda n: {"dtype": "float32", "shape": (n,), "names": None}  # noqa: E731
    spec = {image_key(c, m): dict(image) for c in cameras for m in modalities}
    spec.update(
        {
            STATE: vector(state_dim(num_hand_joints)),
            ACTION: vector(action_dim),
            WORLD_STATE: vector(world_state_dim(num_hand_joints)),
            WORLD_ACTION: vector(action_dim),
            GRASP_POINT_BASE: vector(3),
            GOAL_POINT_BASE: vector(3),
        }
    )
    return spec

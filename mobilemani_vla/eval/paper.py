"""The paper's MobileManiVLA results that our VLA tables sit beside, and the runs and splits they match."""

from __future__ import annotations

from mobilemani_vla.config import CAMERAS, STATES

PROTOCOL_SPLIT = "test_objects_test_scenes"
# The run the paper's seen/unseen table reads: the main model of the ablation study.
SPLIT_RUN = "ablation_image_all"
# Paper, MobileManiVLA per skill (G1, XHand) and mean.
PAPER_BY_SKILL = {
    "open": (42.9, 34.5),
    "close": (75.8, 77.5),
    "pull": (34.4, 29.4),
    "push": (85.1, 90.0),
    "pick": (28.8, 40.2),
    "mean": (56.7, 57.3),
}
# Paper, MobileManiVLA per category: open/pull/pick G1, XHand; close/push G1, XHand.
PAPER_BY_CATEGORY = {
    "box": (55.0, 22.5, 61.9, 95.0),
    "toilet": (63.5, 42.0, 64.5, 95.0),
    "laptop": (74.6, 64.6, 67.9, 98.8),
    "trashcan": (41.4, 37.9, 51.8, 76.4),
    "dishwasher": (93.5, 86.0, 99.5, 97.0),
    "oven": (93.8, 77.5, 90.0, 97.5),
    "microwave": (32.5, 42.5, 42.2, 85.0),
    "refrigerator": (18.1, 12.8, 91.3, 77.5),
    "washing_machine": (40.0, 67.5, 65.0, 67.5),
    "car": (28.7, 26.2, 97.5, 90.0),
    "safe": (35.6, 30.0, 96.9, 98.8),
    "fridge": (37.5, 10.0, 95.0, 95.0),
    "cabinet": (40.0, 33.8, 91.2, 91.2),
    "window": (34.2, 11.7, 90.8, 94.2),
    "lever_door": (55.6, 58.1, 94.0, 94.5),
    "round_door": (41.0, 71.5, 92.5, 95.7),
    "faucet": (41.4, 31.7, 34.3, 38.1),
    "table": (25.8, 19.7, 96.4, 93.9),
    "cart": (34.4, 29.4, 85.0, 90.0),
    "holistic": (28.8, 40.2, None, None),
}
# Ablation rows: run name, cameras, states, paper success (G1, ablation subset).
IMAGE_ABLATION = [
    ("ablation_image_head_rgb", CAMERAS[:1], STATES[:1], 7.9),
    ("ablation_image_head_rgbd", CAMERAS[:2], STATES[:1], 14.1),
    ("ablation_image_head_wrist_rgb", ("head_rgb", "wrist_rgb"), STATES[:1], 14.9),
    ("ablation_image_all", CAMERAS, STATES[:1], 28.2),
]
STATE_ABLATION = [
    ("ablation_state_none", CAMERAS, (), 22.4),
    ("ablation_image_all", CAMERAS, STATES[:1], 28.2),  # the main model, as the image table's last row
    ("ablation_state_grasp_point", CAMERAS, STATES[:2], 32.3),
    ("ablation_state_goal_point", CAMERAS, STATES, 36.6),
]
# The four object x scene splits of the seen/unseen table.
SEEN_SEEN, SEEN_UNSEEN, UNSEEN_SEEN = (
    "train_objects_train_scenes",
    "train_objects_test_scenes",
    "test_objects_train_scenes",
)
# Seen/unseen rows: split file, label, paper success.
SPLITS = [
    (SEEN_SEEN, "seen objects, seen scenes", 59.6),
    (SEEN_UNSEEN, "seen objects, unseen scenes", 51.3),
    (UNSEEN_SEEN, "unseen objects, seen scenes", 39.2),
    (PROTOCOL_SPLIT, "unseen objects, unseen scenes", 28.2),
]
# Model comparison: label, run name, paper success (G1, ablation subset; None: not in the paper). The stock
# LeRobot policies are the ablation study's baselines (mobilemani_vla.ablation_study).
MODELS = [
    ("OpenVLA (7B)", "openvla", 4.5),
    ("CogACT (7B)", "cogact", 6.8),
    ("pi0 (3B)", "pi0", 11.2),
    ("pi0.5 (3B)", "pi05", 18.8),
    ("ACT", "ablation_act", None),
    ("Diffusion Policy", "ablation_diffusion", None),
    ("SmolVLA (from scratch)", "ablation_smolvla", None),
    ("MobileManiVLA", "ablation_image_all", 28.2),
]


def paper_success(run: str, split: str) -> float | None:
    """The paper's success (%) for one of our (run, split) results files: an ablation row on the protocol's
    split, or the main model on a seen/unseen split; None where the paper has no such number."""
    if split == PROTOCOL_SPLIT:
        rows = [(r, p) for r, *_, p in IMAGE_ABLATION + STATE_ABLATION] + [(r, p) for _, r, p in MODELS]
        return dict(rows).get(run)
    return {s: p for s, _, p in SPLITS}.get(split) if run == SPLIT_RUN else None

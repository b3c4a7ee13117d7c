"""Reward terms, grasp flag and success (docs/reference.md, "Rewards, success, termination"). Every term is
returned separately for logging."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from mobilemani_rl.envs.config import RewardWeights, SuccessCfg
from mobilemani_rl.envs.frames import EnvRows, Frames
from mobilemani_rl.utils.rotations import (
    euler_from_quat,
    mean_last,
    quat_between_vectors,
    quat_conj,
    quat_mul,
    vector_norm,
)

GRASP_DIRECTION = np.array([0.0, 1.0, 0.0])  # articulated and YCB tasks alike


@dataclass
class TaskDistances(EnvRows):
    """Point distances to the single grasp point;
    shared by rewards and observations."""

    hand: np.ndarray  # (n,) d_h: palm point to grasp point
    finger: np.ndarray  # (n, F) each finger point; the thumb (or outer finger) last
    body: np.ndarray  # (n, B) each active body origin
    goal: np.ndarray  # (n,) grasp point to goal

    @property
    def thumb(self) -> np.ndarray:
        return self.finger[:, -1]

    @property
    def fingers(self) -> np.ndarray:
        return mean_last(self.finger)

    @property
    def bodies(self) -> np.ndarray:
        return mean_last(self.body)

    @classmethod
    def measure(cls, frames: Frames, goal_pos: np.ndarray) -> TaskDistances:
        points = np.concatenate(
            (frames.palm_pos[:, None], frames.finger_pos, frames.body_pos, goal_pos[:, None]), axis=1
        )
        distance = vector_norm(points - frames.grasp_pos[:, None])  # one norm for all points
        num_fingers = frames.finger_pos.shape[1]
        return cls(
            hand=distance[:, 0],
            finger=distance[:, 1 : 1 + num_fingers],
            body=distance[:, 1 + num_fingers : -1],
            goal=distance[:, -1],
        )


def grasp_flag(d: TaskDistances, cfg: SuccessCfg) -> np.ndarray:
    return (d.hand <= cfg.reach_radius) & (d.thumb <= cfg.finger_radius) & (d.fingers <= cfg.finger_radius)


def palm_direction(palm_quat: np.ndarray) -> np.ndarray:
    """The palm direction, the hand body's local +z in the world: the third column of its rotation matrix."""
    w, x, y, z = palm_quat[..., 0], palm_quat[..., 1], palm_quat[..., 2], palm_quat[..., 3]
    return np.stack((2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)), axis=-1)


def rotation_to(palm_quat: np.ndarray, target_dir: np.ndarray) -> np.ndarray:
    """Clipped RPY of the shortest-arc rotation taking the palm direction onto target_dir (which may carry
    extra leading axes: the palm direction broadcasts)."""
    return np.clip(euler_from_quat(quat_between_vectors(palm_direction(palm_quat), target_dir)), -1.0, 1.0)


def rotation_onto(palm_quat: np.ndarray, target_quat: np.ndarray) -> np.ndarray:
    """Clipped RPY of the world-frame rotation taking the palm orientation onto target_quat."""
    return np.clip(euler_from_quat(quat_mul(target_quat, quat_conj(palm_quat))), -1.0, 1.0)


@dataclass(frozen=True)
class RewardContext:
    """Per-env constants of the current episodes that rewards need besides the frames."""

    goal_pos: np.ndarray  # (n, 3)
    goal_scale: np.ndarray  # (n,) D0, the default goal distance
    default_hand_action: np.ndarray  # (nh,) normalised default hand joint positions
    palm_rot_target: np.ndarray | None  # (n, 4) q_rot90, or None where the palm-rotation term is off


def reward_terms(
    frames: Frames,
    actions: np.ndarray,
    ctx: RewardContext,
    d: TaskDistances,
    grasped: np.ndarray,
    success_cfg: SuccessCfg,
) -> dict[str, np.ndarray]:
    """Unweighted reward terms (docs/reference.md, "Reward terms"), each already gated by its activity
    condition."""
    reaching = (d.hand > success_cfg.reach_radius).astype(np.float64)
    holding = grasped.astype(np.float64)
    n = actions.shape[0]
    pos_target = np.clip(frames.grasp_pos - frames.palm_pos, -1.0, 1.0)
    hand_target = np.clip(ctx.default_hand_action, -1.0, 1.0)
    to_goal = ctx.goal_pos - frames.grasp_pos
    move_pos_target = np.clip(to_goal / ctx.goal_scale[:, None], -1.0, 1.0)
    away_from_motion = -to_goal / np.maximum(vector_norm(to_goal, keepdims=True), 1e-9)
    # Reach (onto the grasp direction) and move (away from the motion) rotation targets in one batched call.
    rot_target, move_rot_target = rotation_to(
        frames.palm_quat, np.stack((np.broadcast_to(GRASP_DIRECTION, (n, 3)), away_from_motion))
    )
    if ctx.palm_rot_target is None:
        palm_rot = np.zeros(n)
    else:
        pitch = rotation_onto(frames.palm_quat, ctx.palm_rot_target)[:, 1]
        palm_rot = np.abs(pitch - actions[:, 4]) * reaching
    # The four wrist-action gaps, (reach, move) x (position, rotation), in one norm.
    wrist = actions[:, :6].reshape(n, 1, 2, 3)
    targets = np.stack((pos_target, rot_target, move_pos_target, move_rot_target), axis=1).reshape(n, 2, 2, 3)
    (reach_pos, reach_rot), (move_pos, move_rot) = np.moveaxis(vector_norm(targets - wrist), 0, -1)
    return {
        "diff_reach_pos_action": reach_pos * reaching,
        "diff_reach_rot_action": reach_rot * reaching,
        "diff_reach_joint_action": vector_norm(hand_target - actions[:, 6:]) * reaching,
        "diff_reach_palm_rot_action": palm_rot,
        "diff_hand_object": d.hand,
        "diff_hand_body_object": d.bodies,
        "diff_hand_thumb_object": d.thumb,
        "diff_hand_finger_object": d.fingers,
        "diff_object_goal": d.goal / ctx.goal_scale,
        "bonus_grasp_object": holding,
        "diff_move_pos_action": move_pos * holding,
        "diff_move_rot_action": move_rot * holding,
        # Hard-coded 0.05 m in the reference, equal to the success threshold.
        "bonus_object_goal": (d.goal < success_cfg.threshold) * holding,
    }


def total_reward(
    terms: dict[str, np.ndarray],
    weights: RewardWeights,
    clip: float,
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Σ w·r, NaN→0, clipped; also the weighted terms by name."""
    names = [f.name for f in fields(weights)]
    weighted = (
        np.stack([terms[name] for name in names])
        * np.array([getattr(weights, name) for name in names])[:, None]
    )
    total = np.clip(weighted.sum(axis=0), -clip, clip)
    total[np.isnan(total)] = 0.0
    return total, dict(zip(names, weighted, strict=True))

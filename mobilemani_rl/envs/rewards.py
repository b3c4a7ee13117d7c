"""Reward terms, grasp flag and success (reference §5). Every term is returned separately for logging."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from mobilemani_rl.envs.config import RewardWeights, SuccessCfg
from mobilemani_rl.envs.frames import EnvRows, Frames
from mobilemani_rl.rotations import (
    euler_from_quat,
    quat_apply,
    quat_between_vectors,
    quat_conj,
    quat_mul,
    vector_norm,
)

GRASP_DIRECTION = np.array([0.0, 1.0, 0.0])  # articulated and YCB tasks alike (reference §5a)
PALM_AXIS = np.array([0.0, 0.0, 1.0])  # palm direction = the hand body's local +z


@dataclass
class TaskDistances(EnvRows):
    """Point distances to the single grasp point (reference §4/§5); shared by rewards and observations."""

    hand: np.ndarray  # (n,) d_h: palm point to grasp point
    finger: np.ndarray  # (n, F) each finger point; the thumb (or outer finger) last
    body: np.ndarray  # (n, B) each active body origin
    goal: np.ndarray  # (n,) grasp point to goal

    @property
    def thumb(self) -> np.ndarray:
        return self.finger[:, -1]

    @property
    def fingers(self) -> np.ndarray:
        return self.finger.mean(axis=1)

    @property
    def bodies(self) -> np.ndarray:
        return self.body.mean(axis=1)

    @classmethod
    def measure(cls, frames: Frames, goal_pos: np.ndarray) -> TaskDistances:
        grasp = frames.grasp_pos
        return cls(
            hand=vector_norm(frames.palm_pos - grasp),
            finger=vector_norm(frames.finger_pos - grasp[:, None]),
            body=vector_norm(frames.body_pos - grasp[:, None]),
            goal=vector_norm(goal_pos - grasp),
        )


def grasp_flag(d: TaskDistances, cfg: SuccessCfg) -> np.ndarray:
    return (d.hand <= cfg.reach_radius) & (d.thumb <= cfg.finger_radius) & (d.fingers <= cfg.finger_radius)


def palm_direction(palm_quat: np.ndarray) -> np.ndarray:
    return quat_apply(palm_quat, np.broadcast_to(PALM_AXIS, palm_quat.shape[:-1] + (3,)))


def rotation_to(palm_quat: np.ndarray, target_dir: np.ndarray) -> np.ndarray:
    """Clipped RPY of the shortest-arc rotation taking the palm direction onto target_dir."""
    return np.clip(euler_from_quat(quat_between_vectors(palm_direction(palm_quat), target_dir)), -1.0, 1.0)


@dataclass(frozen=True)
class RewardContext:
    """Per-env constants of the current episodes that rewards need besides the frames."""

    goal_pos: np.ndarray  # (n, 3)
    goal_scale: np.ndarray  # (n,) D0, the default goal distance
    default_hand_action: np.ndarray  # (nh,) normalised default hand joint positions
    palm_rot_target: np.ndarray | None  # (n, 4) q_rot90, or None where the palm-rotation term is off


def reward_terms(frames: Frames, actions: np.ndarray, ctx: RewardContext, d: TaskDistances, grasped: np.ndarray,
                 success_cfg: SuccessCfg) -> dict[str, np.ndarray]:
    """Unweighted reward terms (reference §5b), each already gated by its activity condition."""
    reaching = (d.hand > success_cfg.reach_radius).astype(np.float64)
    holding = grasped.astype(np.float64)
    n = actions.shape[0]
    pos_target = np.clip(frames.grasp_pos - frames.palm_pos, -1.0, 1.0)
    rot_target = rotation_to(frames.palm_quat, np.broadcast_to(GRASP_DIRECTION, (n, 3)))
    hand_target = np.clip(ctx.default_hand_action, -1.0, 1.0)
    to_goal = ctx.goal_pos - frames.grasp_pos
    move_pos_target = np.clip(to_goal / ctx.goal_scale[:, None], -1.0, 1.0)
    away_from_motion = -to_goal / np.maximum(vector_norm(to_goal, keepdims=True), 1e-9)
    move_rot_target = rotation_to(frames.palm_quat, away_from_motion)
    if ctx.palm_rot_target is None:
        palm_rot = np.zeros(n)
    else:
        pitch = np.clip(euler_from_quat(quat_mul(ctx.palm_rot_target, quat_conj(frames.palm_quat)))[:, 1], -1, 1)
        palm_rot = np.abs(pitch - actions[:, 4]) * reaching
    return {
        "diff_reach_pos_action": vector_norm(pos_target - actions[:, 0:3]) * reaching,
        "diff_reach_rot_action": vector_norm(rot_target - actions[:, 3:6]) * reaching,
        "diff_reach_joint_action": vector_norm(hand_target - actions[:, 6:]) * reaching,
        "diff_reach_palm_rot_action": palm_rot,
        "diff_hand_object": d.hand,
        "diff_hand_body_object": d.bodies,
        "diff_hand_thumb_object": d.thumb,
        "diff_hand_finger_object": d.fingers,
        "diff_object_goal": d.goal / ctx.goal_scale,
        "bonus_grasp_object": holding,
        "diff_move_pos_action": vector_norm(move_pos_target - actions[:, 0:3]) * holding,
        "diff_move_rot_action": vector_norm(move_rot_target - actions[:, 3:6]) * holding,
        # Hard-coded 0.05 m in the reference, equal to the success threshold.
        "bonus_object_goal": (d.goal < success_cfg.threshold) * holding,
    }


def total_reward(terms: dict[str, np.ndarray], weights: RewardWeights, clip: float,
                 ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Σ w·r, NaN→0, clipped; also the weighted terms by name."""
    weighted = {f.name: getattr(weights, f.name) * terms[f.name] for f in fields(weights)}
    total = np.nan_to_num(sum(weighted.values()), nan=0.0)
    return np.clip(total, -clip, clip), weighted

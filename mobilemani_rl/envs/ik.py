"""One damped-least-squares IK step per control step over the base yaw, base slide and 7 arm joints."""

from __future__ import annotations

import numpy as np

from mobilemani_rl.rotations import axis_angle_from_quat, quat_from_euler


def wrist_pose_error(actions: np.ndarray, pos_scale: float, rot_scale: float) -> np.ndarray:
    """World-frame pose error (position; rotation vector) of the commanded wrist delta, (n, 6).

    The goal is hand_pos + a[0:3]·pos_scale and quat(euler(a[3:6]·rot_scale)) ⊗ hand_quat (a left-multiplied,
    world-frame rotation, reference §3), so its error from the current hand pose is the delta itself. The
    reference expresses this error in the root frame but leaves the Jacobian in the world frame; both are in
    the world frame here (DESIGN: reproduce behaviour, not the frame quirk).
    """
    rotation = quat_from_euler(actions[:, 3:6] * rot_scale)
    return np.concatenate((actions[:, 0:3] * pos_scale, axis_angle_from_quat(rotation)), axis=1)


def dls_step(jacobian: np.ndarray, error: np.ndarray, damping: float) -> np.ndarray:
    """Δq = Jᵀ (J Jᵀ + λ² I)⁻¹ e for a batch: jacobian (n, 6, k), error (n, 6) -> (n, k)."""
    jjt = jacobian @ np.swapaxes(jacobian, 1, 2)
    jjt += (damping**2) * np.eye(jacobian.shape[1])
    return np.einsum("nij,ni->nj", jacobian, np.linalg.solve(jjt, error[..., None])[..., 0])

"""One damped-least-squares IK step per control step over the base yaw, base slide and 7 arm joints."""

from __future__ import annotations

import numpy as np

from mobilemani_rl.utils.rotations import axis_angle_from_quat, cross, quat_from_euler


def wrist_pose_error(actions: np.ndarray, pos_scale: float, rot_scale: float) -> np.ndarray:
    """World-frame pose error (position; rotation vector) of the commanded wrist delta, (n, 6).

    The goal is hand_pos + a[0:3]·pos_scale and quat(euler(a[3:6]·rot_scale)) ⊗ hand_quat (a left-multiplied,
    world-frame rotation, as in the reference), so its error from the current hand pose is the delta itself.
    The reference expresses this error in the root frame but leaves the Jacobian in the world frame; both are
    in the world frame here (we reproduce the behaviour, not the frame quirk).
    """
    rotation = quat_from_euler(actions[:, 3:6] * rot_scale)
    return np.concatenate((actions[:, 0:3] * pos_scale, axis_angle_from_quat(rotation)), axis=1)


def chain_jacobian(
    point: np.ndarray, anchors: np.ndarray, axes: np.ndarray, is_hinge: np.ndarray
) -> np.ndarray:
    """Geometric Jacobian (n, 6, k) of a world point moved by a serial chain of 1-DoF joints.

    anchors/axes: (n, k, 3) world joint anchors and unit axes (MuJoCo's xanchor/xaxis). Hinge column:
    [a × (p − anchor); a]; slide column: [a; 0]. Equal to mj_jac restricted to these dofs when the point's
    body is downstream of all of them, and cheaper than a per-sim mj_jac call.
    """
    linear = np.where(is_hinge[:, None], cross(axes, point[:, None, :] - anchors), axes)
    angular = axes * is_hinge[:, None]
    return np.concatenate((np.swapaxes(linear, 1, 2), np.swapaxes(angular, 1, 2)), axis=1)


def dls_step(jacobian: np.ndarray, error: np.ndarray, damping: float) -> np.ndarray:
    """Δq = Jᵀ (J Jᵀ + λ² I)⁻¹ e for a batch: jacobian (n, 6, k), error (n, 6) -> (n, k)."""
    jjt = jacobian @ np.swapaxes(jacobian, 1, 2)
    jjt += (damping**2) * np.eye(jacobian.shape[1])
    return (np.linalg.solve(jjt, error[..., None]).swapaxes(1, 2) @ jacobian)[:, 0]

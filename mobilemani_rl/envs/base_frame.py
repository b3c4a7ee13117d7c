"""Conversions between the env-local world frame and the robot base frame (states and actions for the VLA).

World-frame actions: a[0:3] is a wrist translation, a[3:6] an RPY rotation applied as a
left-multiplied world-frame delta, a[6:] hand joints. In the base frame the translation is rotated by the base
orientation and the rotation delta is conjugated: R_base = B⁻¹ R_world B, so a zero rotation stays zero.
The reference's released data instead stores RPY(B⁻¹ ⊗ R_world) (a left product that
maps a zero rotation to the negative base orientation);
`convention="reference"` reproduces it for compatibility.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from mobilemani_rl.utils.rotations import euler_from_quat, quat_apply, quat_conj, quat_from_euler, quat_mul

Convention = Literal["conjugate", "reference"]


def points_to_base(points: np.ndarray, base_pos: np.ndarray, base_quat: np.ndarray) -> np.ndarray:
    """World points (n, 3) -> base frame."""
    return quat_apply(quat_conj(base_quat), points - base_pos)


def _rotate_action(action: np.ndarray, q: np.ndarray, convention: Convention) -> np.ndarray:
    """The translation rotated by q; the rotation delta left-multiplied by q ("reference") or conjugated."""
    out = np.array(action, dtype=np.float64, copy=True)
    out[..., 0:3] = quat_apply(q, action[..., 0:3])
    rotation = quat_mul(q, quat_from_euler(action[..., 3:6]))
    if convention != "reference":
        rotation = quat_mul(rotation, quat_conj(q))
    out[..., 3:6] = euler_from_quat(rotation)
    return out


def action_to_base(
    action: np.ndarray, base_quat: np.ndarray, convention: Convention = "conjugate"
) -> np.ndarray:
    return _rotate_action(action, quat_conj(base_quat), convention)


def action_to_world(
    action: np.ndarray, base_quat: np.ndarray, convention: Convention = "conjugate"
) -> np.ndarray:
    """Inverse of `action_to_base` (the env's VLA mode decodes base-frame actions this way)."""
    return _rotate_action(action, base_quat, convention)

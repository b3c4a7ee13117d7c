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

from mobilemani_rl.rotations import euler_from_quat, quat_apply, quat_conj, quat_from_euler, quat_mul

Convention = Literal["conjugate", "reference"]


def points_to_base(points: np.ndarray, base_pos: np.ndarray, base_quat: np.ndarray) -> np.ndarray:
    """World points (n, 3) -> base frame."""
    return quat_apply(quat_conj(base_quat), points - base_pos)


def pose_to_base(
    pos: np.ndarray, quat: np.ndarray, base_pos: np.ndarray, base_quat: np.ndarray
) -> np.ndarray:
    """World pose -> base-frame (position, RPY), (n, 6)."""
    local = quat_mul(quat_conj(base_quat), quat)
    return np.concatenate((points_to_base(pos, base_pos, base_quat), euler_from_quat(local)), axis=-1)


def action_to_base(
    action: np.ndarray, base_quat: np.ndarray, convention: Convention = "conjugate"
) -> np.ndarray:
    inverse = quat_conj(base_quat)
    out = np.array(action, dtype=np.float64, copy=True)
    out[..., 0:3] = quat_apply(inverse, action[..., 0:3])
    rotation = quat_from_euler(action[..., 3:6])
    if convention == "reference":
        local = quat_mul(inverse, rotation)
    else:
        local = quat_mul(quat_mul(inverse, rotation), base_quat)
    out[..., 3:6] = euler_from_quat(local)
    return out


def action_to_world(
    action: np.ndarray, base_quat: np.ndarray, convention: Convention = "conjugate"
) -> np.ndarray:
    """Inverse of `action_to_base` (the env's VLA mode decodes base-frame actions this way)."""
    out = np.array(action, dtype=np.float64, copy=True)
    out[..., 0:3] = quat_apply(base_quat, action[..., 0:3])
    local = quat_from_euler(action[..., 3:6])
    if convention == "reference":
        world = quat_mul(base_quat, local)
    else:
        world = quat_mul(quat_mul(base_quat, local), quat_conj(base_quat))
    out[..., 3:6] = euler_from_quat(world)
    return out

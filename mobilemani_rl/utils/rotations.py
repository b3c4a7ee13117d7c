"""Batched rotation helpers on numpy arrays.

Conventions follow the reference code: quaternions are (w, x, y, z); Euler angles are (roll, pitch, yaw) with
R = Rz(yaw) @ Ry(pitch) @ Rx(roll). Every function broadcasts over leading axes.
"""

from __future__ import annotations

import numpy as np

Array = np.ndarray


# numpy adds fewer than this many values along an axis one after another, beyond it pairwise.
_SEQUENTIAL_SUM_LIMIT = 8


def sum_last(v: Array, keepdims: bool = False) -> Array:
    """np.sum over the last axis, bit for bit: over a short axis (3-vectors, quaternions, a hand's fingers)
    numpy adds the values in order, and so does this, as whole-array additions, several times faster than
    numpy's reduction, which loops over the short axis once per leading element."""
    k = v.shape[-1]
    if not 0 < k < _SEQUENTIAL_SUM_LIMIT:
        return np.sum(v, axis=-1, keepdims=keepdims)
    total = v[..., 0].copy()
    for i in range(1, k):
        total += v[..., i]
    return total[..., None] if keepdims else total


def mean_last(v: Array) -> Array:
    """np.mean over the last axis, bit for bit (its sum divided by the count)."""
    return sum_last(v) / v.shape[-1]


def vector_norm(v: Array, keepdims: bool = False) -> Array:
    """Euclidean norm over the last axis (np.linalg.norm's argument handling dominates on small batches)."""
    return np.sqrt(sum_last(v * v, keepdims=keepdims))


def cross(a: Array, b: Array) -> Array:
    """Cross product over the last axis (np.cross's generic path is several times slower on small batches)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0), axis=-1)


def quat_mul(q1: Array, q2: Array) -> Array:
    """Hamilton product q1 ⊗ q2."""
    w1, x1, y1, z1 = q1[..., 0], q1[..., 1], q1[..., 2], q1[..., 3]
    w2, x2, y2, z2 = q2[..., 0], q2[..., 1], q2[..., 2], q2[..., 3]
    return np.stack(
        (
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ),
        axis=-1,
    )


def quat_conj(q: Array) -> Array:
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def quat_apply(q: Array, v: Array) -> Array:
    """Rotate vectors v by unit quaternions q."""
    w = q[..., :1]
    u = q[..., 1:]
    t = 2.0 * cross(u, v)
    return v + w * t + cross(u, t)


def quat_from_euler(euler: Array) -> Array:
    """(roll, pitch, yaw) -> quaternion, R = Rz·Ry·Rx."""
    half = 0.5 * np.asarray(euler)
    cr, cp, cy = np.cos(half[..., 0]), np.cos(half[..., 1]), np.cos(half[..., 2])
    sr, sp, sy = np.sin(half[..., 0]), np.sin(half[..., 1]), np.sin(half[..., 2])
    return np.stack(
        (
            cr * cp * cy + sr * sp * sy,
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
        ),
        axis=-1,
    )


def euler_from_quat(q: Array) -> Array:
    """Quaternion -> (roll, pitch, yaw), the inverse of `quat_from_euler` (pitch in [-pi/2, pi/2])."""
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    roll = np.arctan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2.0 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return np.stack((roll, pitch, yaw), axis=-1)


def quat_from_yaw(yaw: Array) -> Array:
    yaw = np.asarray(yaw, dtype=float)
    zeros = np.zeros_like(yaw)
    return np.stack((np.cos(0.5 * yaw), zeros, zeros, np.sin(0.5 * yaw)), axis=-1)


def quat_from_matrix(mat: Array) -> Array:
    """Rotation matrices (..., 3, 3) -> unit quaternions with w >= 0
    (Shepperd's method, branch-free select)."""
    m = np.asarray(mat)
    m00, m11, m22 = m[..., 0, 0], m[..., 1, 1], m[..., 2, 2]
    candidates = np.stack(
        (
            np.stack(
                (
                    1 + m00 + m11 + m22,
                    m[..., 2, 1] - m[..., 1, 2],
                    m[..., 0, 2] - m[..., 2, 0],
                    m[..., 1, 0] - m[..., 0, 1],
                ),
                axis=-1,
            ),
            np.stack(
                (
                    m[..., 2, 1] - m[..., 1, 2],
                    1 + m00 - m11 - m22,
                    m[..., 0, 1] + m[..., 1, 0],
                    m[..., 0, 2] + m[..., 2, 0],
                ),
                axis=-1,
            ),
            np.stack(
                (
                    m[..., 0, 2] - m[..., 2, 0],
                    m[..., 0, 1] + m[..., 1, 0],
                    1 - m00 + m11 - m22,
                    m[..., 1, 2] + m[..., 2, 1],
                ),
                axis=-1,
            ),
            np.stack(
                (
                    m[..., 1, 0] - m[..., 0, 1],
                    m[..., 0, 2] + m[..., 2, 0],
                    m[..., 1, 2] + m[..., 2, 1],
                    1 - m00 - m11 + m22,
                ),
                axis=-1,
            ),
        ),
        axis=-2,
    )
    best = np.argmax(np.stack((m00 + m11 + m22, m00, m11, m22), axis=-1), axis=-1)
    q = np.take_along_axis(candidates, best[..., None, None], axis=-2)[..., 0, :]
    q = q / vector_norm(q, keepdims=True)
    return q * np.where(q[..., :1] < 0, -1.0, 1.0)


def axis_angle_from_quat(q: Array) -> Array:
    """Unit quaternion -> rotation vector (axis * angle), angle in [0, pi]."""
    q = q * np.where(q[..., :1] < 0, -1.0, 1.0)
    sin_half = vector_norm(q[..., 1:], keepdims=True)
    angle = 2.0 * np.arctan2(sin_half, q[..., :1])
    # angle / sin(angle/2) -> 2 as the angle -> 0.
    scale = np.where(sin_half > 1e-8, angle / np.maximum(sin_half, 1e-12), 2.0)
    return q[..., 1:] * scale


def quat_between_vectors(a: Array, b: Array) -> Array:
    """Shortest-arc rotation taking direction a to direction b (antiparallel: 180° about an orthogonal axis).

    q = (|a||b| + a·b, a × b), normalised: no need to normalise a and b first.
    """
    a, b = np.broadcast_arrays(a, b)
    scale = np.sqrt(sum_last(a * a, keepdims=True) * sum_last(b * b, keepdims=True))
    q = np.concatenate((scale + sum_last(a * b, keepdims=True), cross(a, b)), axis=-1)
    antiparallel = q[..., 0] < 1e-6 * scale[..., 0]
    if antiparallel.any():  # rare: any axis orthogonal to a will do
        a_anti = a[antiparallel]
        helper = np.where(
            np.abs(a_anti[:, :1]) < 0.9 * vector_norm(a_anti, keepdims=True),
            np.array([1.0, 0.0, 0.0]),
            np.array([0.0, 1.0, 0.0]),
        )
        q[antiparallel] = np.concatenate((np.zeros((len(a_anti), 1)), cross(a_anti, helper)), axis=-1)
    return q / vector_norm(q, keepdims=True)

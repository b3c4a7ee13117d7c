"""The env's action input: exactly one (num_envs, action_dim) row per env, clamped, NaN counted then zeroed."""

from __future__ import annotations

import numpy as np


def checked_actions(actions: np.ndarray, num_envs: int, action_dim: int) -> tuple[np.ndarray, np.ndarray]:
    """Actions as float64, clamped to [-1, 1], NaN entries set to 0 as the reference does; and the number of NaN
    entries of each env's row, so that callers can report them instead of hiding them. Any other shape is an
    error: numpy would broadcast a single row, or a (num_envs, 1) column, to every env and joint."""
    actions = np.asarray(actions, dtype=np.float64)
    if actions.shape != (num_envs, action_dim):
        raise ValueError(f"actions must have shape (num_envs, action_dim) = ({num_envs}, {action_dim}), "
                         f"got {actions.shape}")
    nan = np.isnan(actions)
    return np.where(nan, 0.0, np.clip(actions, -1.0, 1.0)), nan.sum(axis=1)

"""The env's action input: exactly one (num_envs, action_dim) row per env, clamped,
NaN counted then zeroed."""

from __future__ import annotations

import numpy as np


def checked_actions(actions: np.ndarray, num_envs: int, action_dim: int) -> tuple[np.ndarray, np.ndarray]:
    """Actions as float64, clamped to [-1, 1], NaN entries set to 0 as the reference does; and the number of
    NaN entries of each env's row, so that callers can report them instead of hiding them. Any other shape is
    an error: numpy would broadcast a single row, or a (num_envs, 1) column, to every env and joint."""
    actions = np.asarray(actions, dtype=np.float64)
    if actions.shape != (num_envs, action_dim):
        raise ValueError(
            f"actions must have shape (num_envs, action_dim) = ({num_envs}, {action_dim}), "
            f"got {actions.shape}"
        )
    nan = np.isnan(actions)
    return np.where(nan, 0.0, np.clip(actions, -1.0, 1.0)), nan.sum(axis=1)


def dart_perturbed(actions: np.ndarray, std: float, rng: np.random.Generator) -> np.ndarray:
    """`actions` plus Gaussian noise of standard deviation `std`, clamped as the env will
    (DART, Laskey et al. 2017). The env executes these while the clean actions are the labels, so
    demonstrations show the teacher correcting deviations like those a policy imitating it makes."""
    return np.clip(actions + std * rng.standard_normal(np.shape(actions)), -1.0, 1.0)

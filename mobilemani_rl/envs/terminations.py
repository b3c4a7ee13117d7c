"""Done terms of one env step, one function each (as mjlab's termination terms): every function returns an
(n,) bool array over envs. `step()` calls them in the reference's order: truncation first, then termination
of the envs that are not truncated."""

from __future__ import annotations

import numpy as np

from mobilemani_rl.envs.config import SuccessCfg
from mobilemani_rl.envs.frames import Frames
from mobilemani_rl.envs.rewards import TaskDistances
from mobilemani_rl.utils.rotations import vector_norm


def time_out_or_held_success(
    episode_length: np.ndarray, max_episode_length: int, success_count: np.ndarray, hold_steps: int
) -> np.ndarray:
    """Truncation: the episode's last step, or success held for `hold_steps` steps. The caller passes the
    success counter before this step's success is added, as the reference does."""
    return (episode_length >= max_episode_length - 1) | (success_count >= hold_steps)


def hand_too_far_or_too_fast(frames: Frames, dist: TaskDistances, cfg: SuccessCfg) -> np.ndarray:
    """Termination (failure): the palm strayed beyond `max_hand_distance` from the grasp point, or the palm or
    the grasp point moves faster than `max_speed`."""
    return (
        (dist.hand > cfg.max_hand_distance)
        | (vector_norm(frames.palm_linvel) > cfg.max_speed)
        | (vector_norm(frames.grasp_linvel) > cfg.max_speed)
    )

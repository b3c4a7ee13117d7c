"""From action chunks to one action per step: CogACT's adaptive ensemble, or a fixed chunk element.

The policy is queried every control step, as in the reference. With the ensemble (`action_index=-1`), the
chunk predicted j steps ago contributes its row j (its prediction for the current step); the newest chunk's
row 0 is the reference, each candidate is weighted by exp(alpha * cos(candidate, reference)), and the weights
are normalised. Chunks too short to reach the current step drop out, so a chunk of 1
(a privileged teacher) reduces to executing it. With `action_index=k >= 0` the newest chunk's row k is
executed instead.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from mobilemani_rl.utils.errors import InputError


@dataclass
class EnsembleCfg:
    action_index: int = -1  # -1: adaptive ensemble; k >= 0: execute element k of the newest chunk
    horizon: int = 4  # K: chunks kept (the reference's pred_action_horizon)
    alpha: float = 0.1  # CogACTInference / deploy.py default


def check_action_index(index: int, chunk_length: int | None) -> None:
    """A fixed `ensemble.action_index` names an element of the policy's chunks (unknown length: not yet)."""
    if chunk_length is not None and index >= chunk_length:
        raise InputError(
            f"ensemble.action_index={index} is outside the policy's chunk of {chunk_length} actions"
        )


def ensemble_weights(candidates: np.ndarray, alpha: float) -> np.ndarray:
    """Normalised weights of candidate actions (m, A), newest first; row 0 is the reference."""
    reference = candidates[0]
    norms = np.linalg.norm(candidates, axis=1) * np.linalg.norm(reference)
    cos = candidates @ reference / np.maximum(norms, 1e-12)  # zero vectors count as orthogonal
    weights = np.exp(alpha * cos)
    return weights / weights.sum()


class AdaptiveEnsembler:
    """The last K chunks of one episode; `update` adds the newest and returns the action for this step."""

    def __init__(self, horizon: int, alpha: float) -> None:
        if horizon < 1:
            raise ValueError(f"ensemble horizon must be >= 1, got {horizon}")
        self.alpha = alpha
        self.chunks: deque[np.ndarray] = deque(maxlen=horizon)

    def reset(self) -> None:
        self.chunks.clear()

    def update(self, chunk: np.ndarray) -> np.ndarray:
        self.chunks.appendleft(np.asarray(chunk, dtype=np.float64))  # chunks[j] was predicted j steps ago
        candidates = np.stack([c[j] for j, c in enumerate(self.chunks) if j < len(c)])
        return ensemble_weights(candidates, self.alpha) @ candidates


class ChunkExecutor:
    """Per-env action selection for a batch of envs; `reset(ids)` when those envs' episodes end."""

    def __init__(self, cfg: EnsembleCfg, num_envs: int) -> None:
        self.cfg = cfg
        self.ensemblers = [AdaptiveEnsembler(cfg.horizon, cfg.alpha) for _ in range(num_envs)]

    def reset(self, ids: np.ndarray | list[int]) -> None:
        for i in ids:
            self.ensemblers[i].reset()

    def __call__(self, chunks: np.ndarray) -> np.ndarray:
        """chunks (n, N, A) -> actions (n, A)."""
        k = self.cfg.action_index
        if k >= 0:
            check_action_index(k, chunks.shape[1])
            return np.asarray(chunks[:, k], dtype=np.float64)
        return np.stack([e.update(c) for e, c in zip(self.ensemblers, chunks, strict=True)])

"""Per-dimension bounds normalisation of actions and states: x -> clip(2 (x - lo) / (hi - lo) - 1, -1, 1).

The bounds are the global minimum and maximum of each dimension over the training split, computed by the
project (`Normalizer.fit`) and saved with every checkpoint. LeRobot 0.6's dataset q01/q99 are count-weighted
means of per-episode quantiles, which clip much of a wrist-pose dimension; global bounds clip no
training value. No dimension is exempt: our gripper/hand actions are continuous in [-1, 1]
(CogACT masks its binary gripper).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import torch

from mobilemani_rl.utils.io import read_json

EPS = 1e-8


class Normalizer:
    def __init__(
        self, bounds: Mapping[str, tuple[list[float] | np.ndarray, list[float] | np.ndarray]]
    ) -> None:
        self.bounds = {
            key: (np.asarray(lo, np.float32), np.asarray(hi, np.float32)) for key, (lo, hi) in bounds.items()
        }

    @classmethod
    def fit(cls, values: Mapping[str, np.ndarray]) -> Normalizer:
        """Bounds of each key from its training values, (n, d) or (n, chunk, d)."""
        empty = [k for k, v in values.items() if np.asarray(v).size == 0]
        if empty:
            raise ValueError(f"no training values to normalise {empty} with")
        flat = {k: np.asarray(v, np.float64).reshape(-1, np.shape(v)[-1]) for k, v in values.items()}
        return cls({k: (v.min(axis=0), v.max(axis=0)) for k, v in flat.items()})

    def _bounds(self, key: str, like: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        lo, hi = self.bounds[key]
        return torch.as_tensor(lo, device=like.device), torch.as_tensor(hi, device=like.device)

    def normalize(self, key: str, x: torch.Tensor) -> torch.Tensor:
        lo, hi = self._bounds(key, x)
        return (2.0 * (x.float() - lo) / (hi - lo + EPS) - 1.0).clamp(-1.0, 1.0)

    def unnormalize(self, key: str, x: torch.Tensor) -> torch.Tensor:
        lo, hi = self._bounds(key, x)
        return (x.float().clamp(-1.0, 1.0) + 1.0) / 2.0 * (hi - lo + EPS) + lo

    def clipped_fraction(self, key: str, values: np.ndarray) -> float:
        """Share of the entries of `values` that normalisation clips to ±1."""
        lo, hi = self.bounds[key]
        scaled = 2.0 * (np.asarray(values, np.float32) - lo) / (hi - lo + EPS) - 1.0
        return float(np.mean(np.abs(scaled) > 1.0 + 1e-6))

    def save(self, path: Path) -> None:
        data = {k: {"min": lo.tolist(), "max": hi.tolist()} for k, (lo, hi) in self.bounds.items()}
        path.write_text(json.dumps(data, indent=1))

    @classmethod
    def load(cls, path: Path) -> Normalizer:
        return cls({k: (v["min"], v["max"]) for k, v in read_json(path).items()})

"""CogACT-style quantile normalisation: x -> clip(2 (x - q01) / (q99 - q01) - 1, -1, 1), per dimension.

No dimension is exempt: our gripper/hand actions are continuous in [-1, 1] (CogACT masks its binary gripper).
Quantiles come from the LeRobot dataset's meta/stats.json and are saved with every checkpoint.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import torch

EPS = 1e-8


class QuantileNormalizer:
    def __init__(self, quantiles: dict[str, tuple[list[float], list[float]]]) -> None:
        self.quantiles = {key: (np.asarray(lo, np.float32), np.asarray(hi, np.float32))
                          for key, (lo, hi) in quantiles.items()}

    @classmethod
    def from_stats(cls, stats: dict[str, dict], keys: list[str]) -> QuantileNormalizer:
        missing = [k for k in keys if k not in stats or "q01" not in stats[k] or "q99" not in stats[k]]
        if missing:
            raise KeyError(f"dataset stats lack q01/q99 for {missing} (meta/stats.json of a LeRobot v3 dataset)")
        return cls({k: (np.ravel(stats[k]["q01"]), np.ravel(stats[k]["q99"])) for k in keys})

    def _bounds(self, key: str, like: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        lo, hi = self.quantiles[key]
        return torch.as_tensor(lo, device=like.device), torch.as_tensor(hi, device=like.device)

    def normalize(self, key: str, x: torch.Tensor) -> torch.Tensor:
        lo, hi = self._bounds(key, x)
        return (2.0 * (x.float() - lo) / (hi - lo + EPS) - 1.0).clamp(-1.0, 1.0)

    def unnormalize(self, key: str, x: torch.Tensor) -> torch.Tensor:
        lo, hi = self._bounds(key, x)
        return (x.float().clamp(-1.0, 1.0) + 1.0) / 2.0 * (hi - lo + EPS) + lo

    def save(self, path: Path) -> None:
        data = {k: {"q01": lo.tolist(), "q99": hi.tolist()} for k, (lo, hi) in self.quantiles.items()}
        path.write_text(json.dumps(data, indent=1))

    @classmethod
    def load(cls, path: Path) -> QuantileNormalizer:
        return cls({k: (v["q01"], v["q99"]) for k, v in json.loads(path.read_text()).items()})

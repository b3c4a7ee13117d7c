"""Confidence intervals and tests of success rates, shared by the teacher and the VLA result tables."""

from __future__ import annotations

import math

import numpy as np


def wilson_interval(successes: int, episodes: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval of a success rate (95% by default): unlike p ± z·se it stays inside [0, 1]
    and does not collapse to a point at 0 or all successes."""
    if episodes == 0:
        return 0.0, 1.0
    p, n = successes / episodes, episodes
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return float(max(0.0, centre - half)), float(min(1.0, centre + half))


def mcnemar_p(only_first: int, only_second: int) -> float:
    """Exact two-sided McNemar test of two policies run on the same episodes: how likely a split of the
    discordant episodes (one policy succeeds, the other fails) at least this uneven is if both are equally
    good (a fair coin per discordant episode)."""
    discordant = only_first + only_second
    fewer = min(only_first, only_second)
    tail = sum(math.comb(discordant, k) for k in range(fewer + 1))
    return min(1.0, 2 * tail / 2**discordant)


def two_proportion_p(successes_a: int, episodes_a: int, successes_b: int, episodes_b: int) -> float:
    """Two-sided p of the pooled two-proportion z-test, for success rates measured on different episodes."""
    pooled = (successes_a + successes_b) / (episodes_a + episodes_b)
    spread = math.sqrt(pooled * (1 - pooled) * (1 / episodes_a + 1 / episodes_b))
    if spread == 0:
        return 1.0
    z = (successes_b / episodes_b - successes_a / episodes_a) / spread
    return math.erfc(abs(z) / math.sqrt(2))

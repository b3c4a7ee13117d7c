"""Progress lines with totals and an ETA for long loops whose per-item lines go to logs
(evaluation, collection).

Interactive loops with many short steps (PPO, the warm start, VLA training) use tqdm bars instead; a line per
unit of work reads better in a SLURM or `tee` log than a carriage-return bar.
"""

from __future__ import annotations

import time


def duration(seconds: float) -> str:
    """'42s', '3m05s', '2h07m'."""
    seconds = round(seconds)
    if seconds < 60:
        return f"{seconds}s"
    if seconds < 3600:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m"


class Progress:
    """Counts finished units of `total` and extrapolates the time left linearly from the rate so far."""

    def __init__(self, total: int, unit: str) -> None:
        self.total, self.unit, self.done = total, unit, 0
        self.start = time.perf_counter()

    def advance(self, units: int = 1) -> str:
        """Count `units` (> 0) more as done; returns e.g. '30/9280 episodes, 1m02s elapsed, ETA 5h19m'."""
        self.done += units
        elapsed = time.perf_counter() - self.start
        left = elapsed / self.done * (self.total - self.done)
        return f"{self.done}/{self.total} {self.unit}, {duration(elapsed)} elapsed, ETA {duration(left)}"

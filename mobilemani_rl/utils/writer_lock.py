"""One writer per output (a training run, a dataset, an evaluation's results): two processes writing the same
checkpoints or files would interleave their work. The lock is a lock file held with `flock`, which the system
releases however its holder ends (kill -9 included), so a dead run never blocks the rerun that resumes it."""

from __future__ import annotations

import fcntl
from pathlib import Path

from mobilemani_rl.utils.errors import InputError

TRAIN_LOCK = "train.lock"  # held in a run directory by the process training it (a PPO teacher or a VLA)


def busy(writer: str, output: object, key: str) -> str:
    """The refusal a second writer gets: what holds `output`, and the `key` that chooses another output."""
    return f"another {writer} is writing {output}; wait for it to end or choose another {key}=..."


class WriterLock:
    """Hold `path` (created if missing) until `release` or the end of a `with` block; InputError(`busy`) at
    once when another process holds it."""

    def __init__(self, path: Path, busy: str) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        self._handle = path.open("a")  # "a": a lock file holds nothing, and opening it changes nothing
        try:
            fcntl.flock(self._handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            self._handle.close()
            raise InputError(busy) from None

    def release(self) -> None:
        self._handle.close()  # closing the file releases its lock

    def __enter__(self) -> WriterLock:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()

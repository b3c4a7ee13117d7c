"""The checkout under test, for tests that run an entry point as a user does (a fresh interpreter)."""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def checkout_env(**extra: str) -> dict[str, str]:
    """This process's environment, with this checkout's packages first on the path and `extra` set."""
    return {**os.environ, "PYTHONPATH": str(ROOT), **extra}

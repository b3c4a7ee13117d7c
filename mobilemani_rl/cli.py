"""What every entry point shares: bad input ends the command with its one-line message, not a traceback."""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable

from mobilemani_rl.registry import InputError


def entry_point[T](main: Callable[..., T]) -> Callable[..., T]:
    """Wrap a Hydra task function: an InputError prints `error: <message>` and exits with status 2 (Hydra
    would print its traceback); any other exception keeps its traceback, as it is a bug to report."""

    @functools.wraps(main)
    def run(*args, **kwargs) -> T:
        try:
            return main(*args, **kwargs)
        except InputError as err:
            print(f"error: {err}", file=sys.stderr)
            sys.exit(2)

    return run

"""What every entry point shares: bad input ends the command with its one-line message, not a traceback."""

from __future__ import annotations

import argparse
import functools
import sys
from collections.abc import Callable
from pathlib import Path

from mobilemani_rl.utils.errors import InputError


def entry_point[T](main: Callable[..., T]) -> Callable[..., T]:
    """Wrap an entry point's main (a Hydra task function or an argparse main): an InputError prints
    `error: <message>` and exits with status 2, as argparse does for its own errors (Hydra would print the
    traceback). So does an output path that runs into a file where a folder must be made; any other exception
    keeps its traceback, as it is a bug to report."""

    @functools.wraps(main)
    def run(*args, **kwargs) -> T:
        try:
            return main(*args, **kwargs)
        except InputError as err:
            print(f"error: {err}", file=sys.stderr)
            sys.exit(2)
        except (FileExistsError, NotADirectoryError) as err:
            file = file_in_the_way(Path(err.filename or ""))
            if file is None:
                raise
            print(
                f"error: cannot make the folder {err.filename}: {file} is a file; choose another path",
                file=sys.stderr,
            )
            sys.exit(2)

    return run


def file_in_the_way(folder: Path) -> Path | None:
    """The file at `folder` or at one of its parents, which stops the folder from being made; None if none."""
    return next((path for path in (folder, *folder.parents) if path.exists() and not path.is_dir()), None)


def count(text: str) -> int:
    """argparse type of a count (envs, episodes, pixels, iterations): an integer of at least 1. argparse's
    error names the option: `argument --episodes: must be at least 1, got 0`."""
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def png_path(text: str) -> Path:
    """argparse type of an image to write: a .png path, checked before the minutes of rendering that
    precede the write (its folder is made then)."""
    if Path(text).suffix.lower() != ".png":
        raise argparse.ArgumentTypeError(f"must name a .png file, got {text}")
    return Path(text)


def seconds(text: str) -> float:
    """argparse type of a time budget: a number of seconds above 0."""
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be above 0, got {text}")
    return value

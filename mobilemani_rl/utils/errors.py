"""Errors for input a user can fix, and the checks that raise them with one clear message naming the key or
file and the valid choices."""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from numbers import Integral


class InputError(ValueError):
    """Bad input the user can fix (a config value, a missing file): the entry points print its message alone,
    without a traceback (mobilemani_rl.utils.cli.entry_point)."""


def first_sentence(err: BaseException) -> str:
    """A library error's first sentence, for a one-line message: torch's weights_only refusal goes on for a
    page of advice, with terminal colour codes."""
    text = re.sub(r"\x1b\[[0-9;]*m", "", str(err)).strip()
    return text.splitlines()[0].split(". ")[0] if text else type(err).__name__


class MissingFileError(InputError, FileNotFoundError):
    """An input file or directory that does not exist; the message names it."""


class OutputExistsError(InputError, FileExistsError):
    """An output made from other inputs or settings is in the way; the message says how to replace it."""


class UnwritableOutputError(InputError):
    """An output location this process cannot create or write (a file in the way of a folder, a read-only file
    system, no permission): the message names it, before any work starts
    (mobilemani_rl.utils.io.check_writable)."""


class UnknownNameError(InputError):
    """An unknown robot, object, skill or scene name."""


class ConfigMismatchError(InputError):
    """Continuing a run (training or evaluation) with settings other than those it was started with."""


def check_choice(value: str, choices: Iterable[str], kind: str) -> str:
    choices = list(choices)
    if value not in choices:
        kinds = f"{kind[:-1]}ies" if kind.endswith("y") else f"{kind}s"
        raise UnknownNameError(f"unknown {kind} {value!r}; valid {kinds}: {', '.join(sorted(choices))}")
    return value


def lookup[T](table: Mapping[str, T], name: str, kind: str) -> T:
    return table[check_choice(name, table, kind)]


def check_torch_device(value: str, key: str) -> str:
    """`cpu`, `cuda` or `cuda:<index>` of a GPU this machine has."""
    import torch  # here: most users of these lookups never need torch, which takes seconds to import

    if value == "cpu":
        return value
    kind, colon, index = value.partition(":")
    if kind != "cuda" or (colon and not index.isdigit()):
        raise InputError(f"{key}={value!r}: valid devices are cpu, cuda and cuda:<index>")
    count = torch.cuda.device_count()
    if int(index or 0) >= count:
        raise InputError(f"{key}={value}: this machine has {count} CUDA device(s); use {key}=cpu")
    return value


def check_values(rules: Iterable[tuple[str, object, bool, str]]) -> None:
    """Each rule: (key, value, whether it holds, what the value must be); stops naming every failing key."""
    bad = [f"{key}={value} ({must})" for key, value, holds, must in rules if not holds]
    if bad:
        raise InputError("invalid values: " + "; ".join(bad))


def is_count(value: object) -> bool:
    """A whole number of at least 1. Hydra types config values, but the Python API takes anything: 2.5 envs
    would reach MuJoCo's constructor, which names no key."""
    return isinstance(value, Integral) and value >= 1


SEED_RULE = "an integer >= 0"  # the wording of every seed check, beside the test it names


def is_seed(value: object) -> bool:
    """What numpy seeds a generator with: a whole number >= 0 (it refuses -1 and 1.5 naming neither key)."""
    return isinstance(value, Integral) and value >= 0


def check_positive(counts: Mapping[str, int | None]) -> None:
    """Counts named by their config keys (None: unset) must be whole numbers >= 1; stops with every offending
    key."""
    bad = {key: value for key, value in counts.items() if value is not None and not is_count(value)}
    if bad:
        raise InputError(
            "these must be whole numbers of at least 1: " + ", ".join(f"{k}={v!r}" for k, v in bad.items())
        )

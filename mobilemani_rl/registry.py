"""Name lookups that fail with one clear message naming the valid choices."""

from __future__ import annotations

from collections.abc import Iterable, Mapping


class UnknownNameError(ValueError):
    """An unknown robot, object, skill or scene name."""


def check_choice(value: str, choices: Iterable[str], kind: str) -> str:
    choices = list(choices)
    if value not in choices:
        raise UnknownNameError(f"unknown {kind} {value!r}; valid {kind}s: {', '.join(sorted(choices))}")
    return value


def lookup[T](table: Mapping[str, T], name: str, kind: str) -> T:
    return table[check_choice(name, table, kind)]

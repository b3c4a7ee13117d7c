"""`python -m mobilemani_rl.assets <command>`: inspect the procedural assets.

Commands: `list` (object counts per category and split), `preview --out PNG` (contact sheet). A command is a
(configure parser, run) pair in COMMANDS; add new ones there. Views of every scene placement need the env:
`python -m mobilemani_rl.envs.scene_sheet`.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # this command renders offscreen; mujoco reads it when imported

import argparse
from collections.abc import Callable
from pathlib import Path

from mobilemani_rl.assets.objects.catalog import CATALOG, CATEGORIES, SPLITS
from mobilemani_rl.utils.cli import count, entry_point, png_path


def _configure_list(parser: argparse.ArgumentParser) -> None:
    parser.set_defaults()


def _run_list(args: argparse.Namespace) -> None:
    counts = {c: dict.fromkeys(SPLITS, 0) for c in CATEGORIES}
    for obj in CATALOG.values():
        counts[obj.category][obj.split] += 1
    print(f"{'category':<16}{'train':>7}{'test':>7}{'total':>7}")
    for category, c in counts.items():
        print(f"{category:<16}{c['train']:>7}{c['test']:>7}{c['train'] + c['test']:>7}")
    train, test = (sum(c[s] for c in counts.values()) for s in SPLITS)
    print(f"{'all':<16}{train:>7}{test:>7}{train + test:>7}")


def _configure_preview(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", type=png_path, default=Path("outputs/objects_preview.png"))
    parser.add_argument("--per-category", type=count, default=3)
    parser.add_argument("--size", type=count, default=200, help="tile size in pixels")
    parser.add_argument("--seed", type=int, default=0, help="which sample objects")


def _run_preview(args: argparse.Namespace) -> None:
    from mobilemani_rl.assets.objects.preview import contact_sheet

    print(contact_sheet(args.out, args.per_category, args.size, args.seed))


COMMANDS: dict[
    str, tuple[str, Callable[[argparse.ArgumentParser], None], Callable[[argparse.Namespace], None]]
] = {
    "list": ("object counts per category and split", _configure_list, _run_list),
    "preview": ("contact sheet of sample objects, closed and opened", _configure_preview, _run_preview),
}


@entry_point
def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="python -m mobilemani_rl.assets", description=__doc__.splitlines()[0]
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for name, (help_text, configure, _) in COMMANDS.items():
        configure(sub.add_parser(name, help=help_text))
    args = parser.parse_args(argv)
    COMMANDS[args.command][2](args)


if __name__ == "__main__":
    main()

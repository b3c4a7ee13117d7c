"""Teacher (MobileManiRL) result tables from evaluation files, laid out like the paper's Tables 2 and 6.

    python -m mobilemani_rl.rl.tables [outputs/rl] [--out outputs/tables/rl]

Collects every `eval_*.json` written by `python -m mobilemani_rl.rl.eval` under the given directory (the
newest per run), averages success per object, then per (category, skill group, robot) and per (skill, robot),
and prints Markdown; `--out` also writes .md and .tex files (checked for writability before anything is read).
The paper's numbers are shown for comparison; with no evaluation files the tables show only those, and a line
names the missing input.
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from pathlib import Path

import numpy as np

from mobilemani_rl.assets.objects import CATEGORIES, OBJECTS, SPLITS, catalog_ids, get_object
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.io import check_writable, read_json
from mobilemani_rl.utils.table_format import Table, pct

ROBOTS = ("g1", "xhand")
FORWARD, BACKWARD = ("open", "pull", "pick"), ("close", "push")
SKILLS = FORWARD + BACKWARD
# MobileManiRL success (%) from the paper, Table 2: G1, XHand.
PAPER_BY_SKILL = {
    "open": (86.6, 91.9),
    "close": (96.2, 96.5),
    "pull": (80.8, 97.3),
    "push": (93.1, 97.2),
    "pick": (66.4, 72.6),
}


def newest_results(root: Path) -> list[dict]:
    """The newest evaluation file of each run directory."""
    newest: dict[Path, Path] = {}
    for path in root.rglob("eval_*.json"):
        if path.parent not in newest or path.stat().st_mtime > newest[path.parent].stat().st_mtime:
            newest[path.parent] = path
    return [read_json(p) for p in newest.values()]


def object_success(results: list[dict], split: str | None = None) -> dict[tuple[str, str, str], float]:
    """(robot, object id, skill) -> success rate over the objects of `split` (None: all evaluated objects)."""
    table = {}
    for result in results:
        task = result["task"]
        for object_id, entry in result["objects"].items():
            if split is None or entry["split"] == split:
                table[(task["robot"], object_id, task["skill"])] = entry["success_rate"]
    return table


def rows(categories: list[str] | None = None, skills: list[str] | None = None) -> list[tuple[str, str]]:
    """(category, skill) rows in catalog order: articulated categories open/close, carts pull/push, pick."""
    return [
        (category, skill)
        for category in categories or CATEGORIES
        for skill in get_object(catalog_ids(category)[0]).skills
        if skills is None or skill in skills
    ]


def trained_rows(success: dict[tuple[str, str, str], float], robot: str) -> int:
    """How many of the table's (category, skill) rows the robot has evaluated objects in."""
    return len({(OBJECTS[object_id].category, skill) for r, object_id, skill in success if r == robot})


def mean_or_none(values: list[float]) -> float | None:
    return float(np.mean(values)) if values else None


def category_table(success: dict[tuple[str, str, str], float]) -> Table:
    grouped: dict[tuple[str, str, str], list[float]] = defaultdict(list)
    for (robot, object_id, skill), rate in success.items():
        group = "forward" if skill in FORWARD else "backward"
        grouped[(OBJECTS[object_id].category, group, robot)].append(rate)
    table_rows = []
    for category in CATEGORIES:
        counts = [
            len(catalog_ids(category)),
            len(catalog_ids(category, "train")),
            len(catalog_ids(category, "test")),
        ]
        cells = [
            pct(mean_or_none(grouped[(category, g, r)])) for g in ("forward", "backward") for r in ROBOTS
        ]
        table_rows.append([category.replace("_", " ").title(), *map(str, counts), *cells])
    header = [
        "Object",
        "Total",
        "Train",
        "Test",
        "Open/Pull/Pick G1",
        "Open/Pull/Pick XHand",
        "Close/Push G1",
        "Close/Push XHand",
    ]
    return Table(
        header, table_rows, "Success rates (%) of MobileManiRL teachers per object category (-: not trained)."
    )


def skill_table(success: dict[tuple[str, str, str], float]) -> Table:
    table_rows = []
    for skill in SKILLS:
        ours = [
            mean_or_none([v for (r, _, s), v in success.items() if r == robot and s == skill])
            for robot in ROBOTS
        ]
        table_rows.append([skill.title(), *map(pct, ours), *(f"{p:.1f}" for p in PAPER_BY_SKILL[skill])])
    means = [mean_or_none(list(v for (r, _, _), v in success.items() if r == robot)) for robot in ROBOTS]
    table_rows.append(["Mean", *map(pct, means), "89.6", "92.9"])
    coverage = ", ".join(
        f"{name} {trained_rows(success, robot)} of {len(rows())}"
        for robot, name in zip(ROBOTS, ("G1", "XHand"), strict=True)
    )
    return Table(
        ["Skill", "G1", "XHand", "G1 (paper)", "XHand (paper)"],
        table_rows,
        "Success rates (%) of MobileManiRL teachers across the 5 skills: each cell averages the evaluated "
        f"objects of the category rows trained ({coverage} rows; -: none trained).",
        separators=(len(SKILLS),),
    )


@entry_point
def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("root", nargs="?", type=Path, default=Path("outputs/rl"))
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--split", choices=SPLITS, default=None, help="only objects of this split")
    args = parser.parse_args()
    if args.out is not None:
        check_writable(args.out, "--out")
    success = object_success(newest_results(args.root), args.split)
    if not success:  # not an error: `make tables` goes on to the VLA tables, which may have results
        print(
            f"missing input: no teacher evaluation (eval_*.json) under {args.root}; `make rl` writes one, or "
            "python -m mobilemani_rl.rl.eval checkpoint=<run>/model_<it>.pt. The teacher tables hold the "
            "paper's numbers only."
        )
    for table in write_tables(success, args.out):
        print(table.markdown())


def write_tables(success: dict[tuple[str, str, str], float], out: Path | None) -> list[Table]:
    """The by-skill and by-category tables, also written to `out` as .md and .tex (None: not written)."""
    tables = {"rl_by_skill": skill_table(success), "rl_by_category": category_table(success)}
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        for name, table in tables.items():
            (out / f"{name}.md").write_text(table.markdown())
            (out / f"{name}.tex").write_text(table.latex())
    return list(tables.values())


if __name__ == "__main__":
    main()

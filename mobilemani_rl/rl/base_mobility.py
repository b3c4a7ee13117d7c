"""The paper's base-mobility ablation (Table 8): G1 teachers with the base fixed beside the mobile ones.

    python -m mobilemani_rl.rl.base_mobility --mobile <teachers_g1.json> --fixed <teachers_g1.json>
        [--out outputs/tables/rl]

Reads the row records the teacher sweep writes (`python -m mobilemani_rl.rl.sweep`, `teachers_g1.json`;
`make teachers-base-ablation` runs both): the mobile rows from `--mobile`, the rows trained with
`env=fixed_base` from `--fixed`. For each of the paper's six combinations it shows the success over the row's
test objects with its episodes and Wilson 95% interval, and the mean over the rows both columns have, with a
normal-approximation interval, beside the paper's 82.8% (mobile) and 25.4% (fixed). Prints Markdown; `--out`
also writes rl_base_mobility.md and .tex. With a file missing it says which and prints the paper's numbers
only.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.io import check_writable, read_json
from mobilemani_rl.utils.stats import wilson_interval
from mobilemani_rl.utils.table_format import Table, pct

# The combinations the paper trains with the base fixed, and its mean success (%) over them (Table 8).
COMBINATIONS = (
    ("laptop", "open"),
    ("cabinet", "open"),
    ("faucet", "open"),
    ("table", "open"),
    ("cart", "pull"),
    ("holistic", "pick"),
)
PAPER = {"mobile": 82.8, "fixed": 25.4}


def row_counts(path: Path) -> dict[tuple[str, str], tuple[int, int]]:
    """(category, skill) -> (successes, episodes) over each row's test objects (none: no file)."""
    counts = {}
    for record in read_json(path) if path.is_file() else []:
        episodes = record["episodes_per_object"]
        successes = sum(round(rate * episodes) for rate in record["test_object_success"].values())
        counts[(record["category"], record["skill"])] = (successes, episodes * record["test_objects"])
    return counts


def rate_cell(counts: tuple[int, int] | None) -> str:
    if counts is None:
        return "-"
    successes, episodes = counts
    low, high = wilson_interval(successes, episodes)
    return f"{pct(successes / episodes)} ({episodes:,}; {pct(low)}-{pct(high)})"


def mean_cell(rows: list[tuple[int, int]]) -> str:
    """The mean of the rows' rates, with the normal approximation of its 95% interval (rows independent)."""
    if not rows:
        return "-"
    rates = np.array([s / n for s, n in rows])
    half = 1.96 * np.sqrt(sum(p * (1 - p) / n for p, (_, n) in zip(rates, rows, strict=True))) / len(rows)
    mean = rates.mean()
    count = f"{len(rows)} row" + "s" * (len(rows) > 1)
    return f"{pct(mean)} ({count}; {pct(max(0.0, mean - half))}-{pct(min(1.0, mean + half))})"


def base_mobility_table(mobile: dict, fixed: dict) -> Table:
    table_rows = [
        [
            f"{category} {skill}",
            rate_cell(mobile.get((category, skill))),
            rate_cell(fixed.get((category, skill))),
        ]
        for category, skill in COMBINATIONS
    ]
    # Means over the rows both columns have, so that a column's missing rows do not move the comparison.
    shared = [row for row in COMBINATIONS if row in mobile and row in fixed]
    means = [mean_cell([column[row] for row in shared]) for column in (mobile, fixed)]
    table_rows.append(["Mean (rows in both)", *means])
    table_rows.append(["Paper (G1)", f"{PAPER['mobile']:.1f}", f"{PAPER['fixed']:.1f}"])
    return Table(
        ["Combination", "Mobile base", "Fixed base"],
        table_rows,
        "Success rates (%) of G1 MobileManiRL teachers with a mobile or a fixed base on test objects "
        "(episodes; Wilson 95% interval; the mean's interval by normal approximation; -: not trained). The "
        "fixed base starts 0.5-1.0 m from the grasp point instead of 1.0-1.5 m.",
        separators=(len(COMBINATIONS),),
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--mobile", type=Path, required=True)
    parser.add_argument("--fixed", type=Path, required=True)
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args(argv)
    if args.out is not None:
        check_writable(args.out, "--out")
    missing = [p for p in (args.mobile, args.fixed) if not p.is_file()]
    if missing:  # not an error: `make tables` goes on to the other tables
        print(
            "missing input: no teacher rows in " + ", ".join(map(str, missing)) + "; `make "
            "teachers-base-ablation` writes them. The base-mobility table holds the paper's numbers only."
        )
    table = base_mobility_table(row_counts(args.mobile), row_counts(args.fixed))
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "rl_base_mobility.md").write_text(table.markdown())
        (args.out / "rl_base_mobility.tex").write_text(table.latex())
    print(table.markdown())


if __name__ == "__main__":
    entry_point(main)()

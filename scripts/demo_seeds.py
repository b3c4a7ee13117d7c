"""The tables of `make demo` runs with different PPO seeds, and of VLA variants trained on one seed's data,
from the records each run left:

    python -m scripts.demo_seeds docs/results/demo

Each `seed_<N>/` folder holds a run's teacher evaluation (`teacher_eval_256.json`), its closed-loop episodes
(`eval_teacher.jsonl`, `eval_vla.jsonl`, `eval_vla_seed1.jsonl`) and the VLA's held-out diagnostics
(`vla_diagnostics.jsonl`), and where measured the same 60 episodes with the VLA's image feature replaced by
its null vector (`eval_vla_null_image.jsonl`, `eval_vla_null_image_seed1.jsonl`; `policy.null_image=true`); a
table gets that column when one of its VLAs has them, and the open-loop column (the sampled chunk's held-out
error with the images and from the null vector alone) when one of its VLAs logged both. The first table gives
the VLA's 60 episodes with their Wilson interval and the spread. Each `seed_<N>/variants/<name>/` folder holds
the VLA records of one more VLA trained on that run's dataset with other settings (its `overrides.txt`); the
next table lists them beside the run's own VLA. Any other `<dataset>/variants/<name>/` folder holds the same
records of a VLA trained on another dataset, which `<dataset>/dataset.txt` names and
`<dataset>/dataset_stats.json` describes; each such dataset gets a table of its own.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from mobilemani_vla.eval.results import read_records
from scripts.demo_report import open_loop_errors, rate_cell

VLA_HEADER = (
    "| VLA, 60 in the test rooms | VLA per room (of 15) | held-out noise error "
    "| minus it: null image / empty instruction / no state |"
)
OPEN_LOOP_HEADER = " open-loop error: images / null vector |"
NULL_IMAGE_HEADER = " the same 60 with a null image |"
NULL_IMAGE_RECORDS = ("eval_vla_null_image.jsonl", "eval_vla_null_image_seed1.jsonl")


def episodes(folder: Path, names: tuple[str, ...]) -> list[dict]:
    return [record for name in names for record in read_records(folder / name)]


def has_null_image(folders: list[Path]) -> bool:
    return any((folder / NULL_IMAGE_RECORDS[0]).is_file() for folder in folders)


def null_image_cell(folder: Path) -> str:
    if not all((folder / name).is_file() for name in NULL_IMAGE_RECORDS):
        return "-"
    return rate_cell(episodes(folder, NULL_IMAGE_RECORDS))


def vla_cells(folder: Path) -> tuple[list[str], float]:
    """A VLA's 60 episodes, per room, and its last held-out diagnostics; and its success rate."""
    vla = episodes(folder, ("eval_vla.jsonl", "eval_vla_seed1.jsonl"))
    rooms = sorted({r["scene"] for r in vla})
    per_room = "/".join(str(sum(r["success"] for r in vla if r["scene"] == room)) for room in rooms)
    diag = last_diagnostics(folder)
    image = diag["noise_mse/image"]
    gaps = " / ".join(
        f"{diag[f'noise_mse/{k}'] - image:+.4f}" if f"noise_mse/{k}" in diag else "-"
        for k in ("null_image", "null_instruction", "no_state")
    )
    return [rate_cell(vla), per_room, f"{image:.4f}", gaps], sum(r["success"] for r in vla) / len(vla)


def last_diagnostics(folder: Path) -> dict:
    return json.loads((folder / "vla_diagnostics.jsonl").read_text().splitlines()[-1])


def open_loop_cell(folder: Path) -> str:
    errors = open_loop_errors(last_diagnostics(folder))
    return "-" if errors is None else f"{errors[1]:.3f} / {errors[2]:.3f}"


def seed_cells(run: Path) -> list[str]:
    """A run's PPO seed and its teacher's two rates."""
    teacher = json.loads((run / "teacher_eval_256.json").read_text())
    closed_loop = rate_cell(read_records(run / "eval_teacher.jsonl"))
    return [run.name.removeprefix("seed_"), f"{100 * teacher['success_rate']:.1f}%", closed_loop]


def vla_table(first_header: str, rows: list[tuple[list[str], Path]]) -> None:
    """One row per (first cells, VLA folder), with the null-image and open-loop columns where one of them has
    those records."""
    folders = [folder for _, folder in rows]
    null = has_null_image(folders)
    open_loop_cells = [open_loop_cell(folder) for folder in folders]  # each record read once
    open_loop = any(cell != "-" for cell in open_loop_cells)
    print_table(
        first_header
        + VLA_HEADER
        + (NULL_IMAGE_HEADER if null else "")
        + (OPEN_LOOP_HEADER if open_loop else ""),
        [
            [
                *first,
                *vla_cells(folder)[0],
                *([null_image_cell(folder)] if null else []),
                *([loop_cell] if open_loop else []),
            ]
            for (first, folder), loop_cell in zip(rows, open_loop_cells, strict=True)
        ],
    )


def print_table(header: str, rows: list[list[str]]) -> None:
    print(header)
    print("|" + "|".join("---" for _ in range(header.count("|") - 1)) + "|")
    for cells in rows:
        print("| " + " | ".join(cells) + " |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path)
    args = parser.parse_args()
    runs = sorted(args.folder.glob("seed_*"), key=lambda run: int(run.name.removeprefix("seed_")))
    vla_table(
        "| PPO seed | teacher, 256 episodes | teacher, 20 in the test rooms ",
        [(seed_cells(run), run) for run in runs],
    )
    rates = [vla_cells(run)[1] for run in runs]
    print(
        f"\nSpread of the VLA over the seeds: {100 * min(rates):.1f}-{100 * max(rates):.1f}% "
        f"({100 * (max(rates) - min(rates)):.1f} points)."
    )
    for run in runs:
        variants = sorted((run / "variants").glob("*"))
        if variants:
            print(f"\nVLAs trained on the dataset of PPO seed {run.name.removeprefix('seed_')}:\n")
            vla_table("| VLA settings ", [(["the demo's"], run), *variant_rows(variants)])
    for dataset in sorted(d for d in args.folder.iterdir() if (d / "dataset.txt").is_file()):
        print(f"\nVLAs trained on {(dataset / 'dataset.txt').read_text().strip()}:\n")
        vla_table("| VLA settings ", variant_rows(sorted((dataset / "variants").glob("*"))))


def variant_rows(variants: list[Path]) -> list[tuple[list[str], Path]]:
    return [([f"`{(v / 'overrides.txt').read_text().strip()}`"], v) for v in variants]


if __name__ == "__main__":
    main()

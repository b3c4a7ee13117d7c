"""The table of `make demo` runs with different PPO seeds, from the records each run left:

    python -m scripts.demo_seeds docs/results/demo

Each `seed_<N>/` folder holds a run's teacher evaluation (`teacher_eval_256.json`), its closed-loop episodes
(`eval_teacher.jsonl`, `eval_vla.jsonl`, `eval_vla_seed1.jsonl`) and the VLA's held-out diagnostics
(`vla_diagnostics.jsonl`); the table gives the VLA's 60 episodes with their Wilson interval and the spread.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from mobilemani_vla.results import read_records
from scripts.demo_report import rate_cell


def seed_row(run: Path) -> tuple[list[str], float]:
    teacher = json.loads((run / "teacher_eval_256.json").read_text())
    vla = read_records(run / "eval_vla.jsonl") + read_records(run / "eval_vla_seed1.jsonl")
    rooms = sorted({r["scene"] for r in vla})
    per_room = "/".join(str(sum(r["success"] for r in vla if r["scene"] == room)) for room in rooms)
    diag = json.loads((run / "vla_diagnostics.jsonl").read_text().splitlines()[-1])
    image = diag["noise_mse/image"]
    gaps = " / ".join(
        f"{diag[f'noise_mse/{k}'] - image:+.4f}" for k in ("null_image", "null_instruction", "no_state")
    )
    cells = [
        run.name.removeprefix("seed_"),
        f"{100 * teacher['success_rate']:.1f}%",
        rate_cell(read_records(run / "eval_teacher.jsonl")),
        rate_cell(vla),
        per_room,
        f"{image:.4f}",
        gaps,
    ]
    return cells, sum(r["success"] for r in vla) / len(vla)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path)
    args = parser.parse_args()
    runs = sorted(args.folder.glob("seed_*"), key=lambda run: int(run.name.removeprefix("seed_")))
    rows = [seed_row(run) for run in runs]
    print(
        "| PPO seed | teacher, 256 episodes | teacher, 20 in the test rooms | VLA, 60 in the test rooms "
        "| VLA per room (of 15) | held-out noise error "
        "| minus it: null image / empty instruction / no state |"
    )
    print("|---|---:|---|---|---|---:|---|")
    for cells, _ in rows:
        print("| " + " | ".join(cells) + " |")
    rates = [rate for _, rate in rows]
    print(
        f"\nSpread of the VLA over the seeds: {100 * min(rates):.1f}-{100 * max(rates):.1f}% "
        f"({100 * (max(rates) - min(rates)):.1f} points)."
    )


if __name__ == "__main__":
    main()

"""One policy's episodes in LeRobot's evaluator and in ours, side by side, per combination:

    python -m scripts.compare_evaluators <lerobot-eval output_dir>/eval_info.json <make eval results>.jsonl...

`lerobot-eval --env.type=mobilemanibench --env.task=T` numbers its task ids in the order our harness runs T's
combinations (lerobot_env_mobilemanibench.tasks), and with the same `--seed` and `--eval.batch_size` as the
harness's `seed` and `episodes_per_batch` its episode e starts as the harness's episode e. Each row pairs
those episodes: the successes in each evaluator and the largest return difference between paired episodes,
which is 0 only where both ran the policy with the same arithmetic. Several harness files (e.g. runs with
different worker counts) give a column each.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from lerobot_env_mobilemanibench.tasks import task_combinations

from mobilemani_vla.eval.results import read_records
from scripts.demo_report import rate_cell


def lerobot_episodes(info_path: Path) -> dict[str, list[dict]]:
    """lerobot-eval's episodes as {combination name: [{"success", "return"}, ...]} in episode order."""
    info = json.loads(info_path.read_text())
    episodes: dict[str, list[dict]] = {}
    names: dict[str, list[str]] = {}
    for task in info["per_task"]:
        group = task["task_group"]
        if group not in names:  # each task's combinations, built once
            names[group] = [c.name for c in task_combinations(group)]
        combos = names[group]
        metrics = task["metrics"]
        episodes[combos[task["task_id"]]] = [
            {"success": bool(s), "return": r}
            for s, r in zip(metrics["successes"], metrics["sum_rewards"], strict=True)
        ]
    return episodes


def harness_episodes(path: Path) -> dict[str, list[dict]]:
    """Our harness's records as {combination name: [record, ...]} in episode order."""
    episodes: dict[str, list[dict]] = {}
    for record in sorted(read_records(path), key=lambda r: r["episode"]):
        name = f"{record['robot']}/{record['object_id']}/{record['skill']}/{record['scene']}"
        episodes.setdefault(name, []).append(record)
    return episodes


def comparison_table(
    lerobot: dict[str, list[dict]], harnesses: dict[str, dict[str, list[dict]]]
) -> list[str]:
    header = ["combination", "lerobot-eval"] + [
        f"harness: {n} (largest return difference)" for n in harnesses
    ]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for name, theirs in lerobot.items():
        cells = [name, f"{sum(e['success'] for e in theirs)}/{len(theirs)}"]
        for runs in harnesses.values():
            ours = runs.get(name, [])
            if len(ours) != len(theirs):
                raise ValueError(f"{name}: lerobot-eval ran {len(theirs)} episodes, the harness {len(ours)}")
            gap = max(abs(a["return"] - b["return"]) for a, b in zip(theirs, ours, strict=True))
            cells.append(f"{sum(e['success'] for e in ours)}/{len(ours)} ({gap:.2f})")
        lines.append("| " + " | ".join(cells) + " |")
    everything = [e for episodes in lerobot.values() for e in episodes]
    total = ["all", rate_cell(everything)]
    for runs in harnesses.values():
        total.append(rate_cell([e for name in lerobot for e in runs[name]]))
    lines.append("| " + " | ".join(total) + " |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("lerobot_eval", type=Path, help="lerobot-eval's eval_info.json")
    parser.add_argument("harness", type=Path, nargs="+", help="make eval's results (.jsonl)")
    args = parser.parse_args()
    harnesses = {path.stem: harness_episodes(path) for path in args.harness}
    print("\n".join(comparison_table(lerobot_episodes(args.lerobot_eval), harnesses)))


if __name__ == "__main__":
    main()

"""MobileManiVLA (closed-loop evaluation) tables and bar plots, laid out like the paper's, from results files.

    python -m mobilemani_vla.eval.tables [outputs/eval] [--out outputs/tables/vla] [--main default]

Reads <root>/<robot>/<run>/<split>.jsonl written by `python -m mobilemani_vla.eval.evaluate` (run = the eval
`name`, by convention the training experiment's name) and writes Markdown + LaTeX for: success per skill and
per category (run `--main`, unseen objects x unseen scenes), the image- and state-input ablations (runs named
like conf/experiment/ablation_*), seen/unseen objects x scenes (run `--split-run`, its four split files) and
the model comparison (runs named in MODELS, then every other run), the paper's takeaways 4-6 tested on these
runs (`mobilemani_vla.eval.takeaways`), plus PNG bar plots. Paper numbers sit
beside ours, a one-number row's with its 95% interval and episode count, and each caption states the training
scale of the runs it shows, as their evaluations recorded it; a '-' marks a result not evaluated yet, and the
results files those cells wanted are listed at the end; `--out` is checked for writability before any result
is read. A table that counts a results file
whose evaluation has not ended (running or stopped: no summary of all its records) names it in its caption,
with its episodes so far.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure  # the object API: no pyplot backend to select, nothing global changed

from mobilemani_rl.assets.objects import CATEGORIES, catalog_ids
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.io import check_writable, read_json
from mobilemani_rl.utils.table_format import Table, num, pct
from mobilemani_vla.config import CAMERAS, STATES
from mobilemani_vla.eval.paper import (
    IMAGE_ABLATION,
    MODELS,
    PAPER_BY_CATEGORY,
    PAPER_BY_SKILL,
    PROTOCOL_SPLIT,
    SPLIT_RUN,
    SPLITS,
    STATE_ABLATION,
)
from mobilemani_vla.eval.results import SKILL_GROUPS, finished, read_records, summarize
from mobilemani_vla.eval.takeaways import takeaway_table

ROBOTS = ("g1", "xhand")
SKILLS = ("open", "close", "pull", "push", "pick")
COLORS = {"g1": "tab:blue", "xhand": "tab:red"}  # ours solid, the paper's the same colour faded
GROUPS = tuple(dict.fromkeys(SKILL_GROUPS.values()))  # open/pull/pick, close/push
# Our side of a one-number row: the success (mean over objects), its interval over the pooled episodes.
RATE_COLUMNS = ("Success", "95% CI", "Episodes")


class RecordingResults(dict):
    """The loaded results, noting every (robot, run, split) a table looks up: the tables name their inputs
    in one place (their own code), so the missing ones can be reported and the unfinished ones marked."""

    def __init__(self, results: dict) -> None:
        super().__init__(results)
        self.missing: set[tuple[str, str, str]] = set()
        self.used: set[tuple[str, str, str]] = set()

    def get(self, key, default=None):
        (self.used if key in self else self.missing).add(key)
        return super().get(key, default)

    def unfinished(self, keys: set[tuple[str, str, str]]) -> str:
        """Those of `keys` whose evaluation has not ended, as printed:
        'g1/default/test_objects_test_scenes (4790 episodes so far), ...'."""
        return ", ".join(
            f"{'/'.join(key)} ({self[key]['episodes']} episodes so far)"
            for key in sorted(keys)
            if not self[key]["finished"]
        )


def load(root: Path) -> RecordingResults:
    """(robot, run, split) -> summary of that results file, its records, whether its evaluation ran to its
    end, and the training its policy holds as the evaluation recorded it (empty for untrained policies)."""
    loaded = {}
    for path in sorted(root.glob("*/*/*.jsonl")):
        records = read_records(path)
        config = path.with_name("config.json")
        loaded[(path.parts[-3], path.parts[-2], path.stem)] = {
            **summarize(records),
            "records": records,
            "finished": finished(path, records),
            "training": read_json(config).get("policy_training", {}) if config.is_file() else {},
        }
    return RecordingResults(loaded)


def training_note(run: str, training: dict) -> str:
    """'g1/run: cpu model, 30,000 steps x 32 = 960,000 samples, from 4,326 episodes (dataset 3f2a9c1e), at
    64 px'; the parts the evaluation recorded."""
    parts = [f"{training['model']} model"] if "model" in training else []
    if "steps" in training:
        parts.append(
            f"{training['steps']:,} steps x {training['batch_size']} = {training['samples']:,} samples"
        )
    if "train_episodes" in training:
        dataset = f" (dataset {training['dataset_sha256'][:8]})" if training.get("dataset_sha256") else ""
        parts.append(f"from {training['train_episodes']:,} episodes{dataset}")
    if training.get("image_size"):
        parts.append(f"at {training['image_size'][0]} px")
    return f"{run}: {', '.join(parts)}"


def interval(summary: dict | None) -> str:
    """The pooled episodes' 95% Wilson interval in percent, '-' where there is no result."""
    if not summary or "overall" not in summary:
        return "-"
    low, high = summary["overall"]["ci95"]
    return f"{100 * low:.1f}-{100 * high:.1f}"


def episode_count(summary: dict | None) -> str:
    return str(summary["episodes"]) if summary and summary.get("episodes") else "-"


def with_interval(summary: dict | None) -> list[str]:
    """A run's overall success, its 95% interval and its episodes, beside the paper's one number."""
    return [pct(rate(summary, "overall")), interval(summary), episode_count(summary)]


def rate(summary: dict | None, *path: str) -> float | None:
    node = summary
    for key in path:
        if not node or key not in node:
            return None
        node = node[key]
    return node["success_rate"]


def check(flag: bool) -> str:
    return "x" if flag else ""


def skill_table(results: dict, run: str) -> Table:
    rows = []
    for skill in (*SKILLS, "mean"):
        path = ("overall",) if skill == "mean" else ("per_skill", skill)
        ours = [rate(results.get((robot, run, PROTOCOL_SPLIT)), *path) for robot in ROBOTS]
        rows.append([skill.title(), *map(pct, ours), *map(num, PAPER_BY_SKILL[skill])])
    return Table(
        ["Skill", "G1", "XHand", "G1 (paper)", "XHand (paper)"],
        rows,
        f"Success rates (%) of run '{run}' (paper: MobileManiVLA) on unseen objects and scenes per skill.",
        separators=(len(SKILLS),),
    )


def category_rates(results: dict, run: str, category: str) -> list[float | None]:
    return [
        rate(results.get((robot, run, PROTOCOL_SPLIT)), "per_category_skill_group", f"{category}|{group}")
        for group in GROUPS
        for robot in ROBOTS
    ]


def category_table(results: dict, run: str) -> Table:
    rows = [
        [
            c.replace("_", " ").title(),
            str(len(catalog_ids(c, "test"))),
            *map(pct, category_rates(results, run, c)),
            *map(num, PAPER_BY_CATEGORY[c]),
        ]
        for c in CATEGORIES
    ]
    cols = [f"{g.title()} {r}" for g in ("Open/Pull/Pick", "Close/Push") for r in ("G1", "XHand")]
    return Table(
        ["Object", "Test", *cols, *(f"{c} (paper)" for c in cols)],
        rows,
        f"Success rates (%) of run '{run}' (paper: MobileManiVLA) per category on unseen objects and scenes.",
    )


def ablation_table(results: dict, rows: list, caption: str) -> Table:
    body = [
        [
            *(check(c in cams) for c in CAMERAS),
            *(check(s in states) for s in STATES),
            *with_interval(results.get(("g1", run, PROTOCOL_SPLIT))),
            num(paper),
        ]
        for run, cams, states, paper in rows
    ]
    header = [
        "Head RGB",
        "Head Depth",
        "Wrist RGB",
        "Wrist Depth",
        "Wrist Pose",
        "Grasp Point",
        "Goal Point",
        *RATE_COLUMNS,
        "Paper",
    ]
    return Table(header, body, caption)


def split_table(results: dict, run: str) -> Table:
    rows = [
        [label, *with_interval(results.get(("g1", run, split))), num(paper)] for split, label, paper in SPLITS
    ]
    return Table(
        ["Objects / scenes", *RATE_COLUMNS, "Paper"],
        rows,
        f"Success rates (%) of run '{run}' (G1) on seen or unseen objects and scenes.",
    )


def model_table(results: dict) -> Table:
    # The ablation rows are MobileManiVLA with other inputs: their own tables show them.
    named = {run for _, run, _ in MODELS} | {row[0] for row in IMAGE_ABLATION + STATE_ABLATION}
    rows = [
        [label, *with_interval(results.get(("g1", run, PROTOCOL_SPLIT))), num(paper)]
        for label, run, paper in MODELS
    ]
    others = sorted(
        {run for robot, run, split in results if robot == "g1" and split == PROTOCOL_SPLIT} - named
    )
    rows += [[run, *with_interval(results.get(("g1", run, PROTOCOL_SPLIT))), "-"] for run in others]
    return Table(
        ["Model", *RATE_COLUMNS, "Paper"],
        rows,
        "Policies on the G1 robot on unseen objects and scenes (our runs; paper models by run name).",
        separators=(len(MODELS),) if others else (),
    )


def _robot_bars(
    ax: Axes, x: np.ndarray, k: int, robot: str, ours: list[float | None], paper: list[float | None]
) -> None:
    """Robot k's two bars at each x: ours (fractions) solid, the paper's (percent) faded; None: a gap."""
    ax.bar(
        x + (2 * k - 1.5) * 0.2,
        [np.nan if v is None else 100 * v for v in ours],
        0.2,
        label=f"{robot} (ours)",
        color=COLORS[robot],
    )
    ax.bar(
        x + (2 * k - 0.5) * 0.2,
        [np.nan if v is None else v for v in paper],
        0.2,
        label=f"{robot} (paper)",
        color=COLORS[robot],
        alpha=0.35,
    )


def bar_plots(results: dict, run: str, out: Path) -> list[Path]:
    """Per-category success (ours vs paper, G1 and XHand) for both skill groups, and per-skill success."""
    paths = []
    fig = Figure(figsize=(14, 8))
    axes = fig.subplots(2, 1, sharey=True)
    x = np.arange(len(CATEGORIES))
    for g, (ax, group) in enumerate(zip(axes, GROUPS, strict=True)):
        for k, robot in enumerate(ROBOTS):
            ours = [category_rates(results, run, c)[2 * g + k] for c in CATEGORIES]
            paper = [PAPER_BY_CATEGORY[c][2 * g + k] for c in CATEGORIES]
            _robot_bars(ax, x, k, robot, ours, paper)
        ax.set_title(f"{group}: success per category ({run}, unseen objects x unseen scenes)")
        ax.set_xticks(
            x, [c.replace("_", " ") for c in CATEGORIES], rotation=30, ha="right", rotation_mode="anchor"
        )
        ax.set_ylabel("success (%)")
        ax.set_ylim(0, 100)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="upper center", ncol=4, fontsize=9)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    paths.append(out / "vla_by_category.png")
    fig.savefig(paths[-1], dpi=120)

    fig = Figure(figsize=(8, 4))
    ax = fig.subplots()
    x = np.arange(len(SKILLS))
    for k, robot in enumerate(ROBOTS):
        ours = [rate(results.get((robot, run, PROTOCOL_SPLIT)), "per_skill", s) for s in SKILLS]
        _robot_bars(ax, x, k, robot, ours, [PAPER_BY_SKILL[s][k] for s in SKILLS])
    ax.set_xticks(x, SKILLS)
    ax.set_ylabel("success (%)")
    ax.set_ylim(0, 110)
    ax.set_title(f"Success per skill ({run}, unseen objects x unseen scenes)")
    ax.legend(ncol=4, fontsize=8, loc="upper center")
    fig.tight_layout()
    paths.append(out / "vla_by_skill.png")
    fig.savefig(paths[-1], dpi=120)
    return paths


def build_tables(results: RecordingResults, main_run: str, split_run: str) -> dict[str, Table]:
    builders = {
        "vla_by_skill": lambda: skill_table(results, main_run),
        "vla_by_category": lambda: category_table(results, main_run),
        "vla_ablation_image": lambda: ablation_table(
            results, IMAGE_ABLATION, "Image-input ablation of MobileManiVLA (G1, ablation subset)."
        ),
        "vla_ablation_state": lambda: ablation_table(
            results, STATE_ABLATION, "State-input ablation of MobileManiVLA (G1, ablation subset)."
        ),
        "vla_seen_unseen": lambda: split_table(results, split_run),
        "vla_models": lambda: model_table(results),
        "vla_takeaways": lambda: takeaway_table(results),
    }
    return {name: annotated(results, build) for name, build in builders.items()}


def annotated(results: RecordingResults, build: Callable[[], Table]) -> Table:
    """The table, its caption stating the training scale of each trained run it shows, as its evaluation
    recorded it, and naming the results it used from evaluations that have not ended (their cells count only
    the episodes run so far)."""
    results.used.clear()
    table = build()
    scales = {
        f"{robot}/{run}": results[robot, run, split]["training"]
        for robot, run, split in sorted(results.used)
        if results[robot, run, split]["training"]
    }
    if scales:
        table.caption += " Our runs: " + "; ".join(training_note(r, t) for r, t in scales.items()) + "."
    if unfinished := results.unfinished(results.used):
        table.caption += f" Unfinished evaluations: {unfinished}."
    return table


def write_tables(root: Path, out: Path, main_run: str, split_run: str) -> None:
    """Every table (Markdown, LaTeX, printed) and bar plot from the results under `root` into `out`, then
    which results were found, which are unfinished and which the tables missed."""
    check_writable(out, "--out")
    results = load(root)
    out.mkdir(parents=True, exist_ok=True)
    for name, table in build_tables(results, main_run, split_run).items():
        print(table.markdown())
        (out / f"{name}.md").write_text(table.markdown())
        (out / f"{name}.tex").write_text(table.latex())
    for path in bar_plots(results, main_run, out):
        print(f"wrote {path}")
    print(f"results under {root}: {', '.join('/'.join(key) for key in sorted(results)) or 'none'}")
    if unfinished := results.unfinished(set(results)):
        print(f"unfinished evaluations (still running or stopped; rerun `make eval` to finish): {unfinished}")
    if results.missing:
        print(
            "missing inputs (their cells show '-'; `make eval NAME=<run> [SPLIT=..]` writes "
            "<robot>/<run>/<split>.jsonl, and --main / MAIN_RUN picks the run of the per-skill and "
            "per-category tables):\n  "
            + "\n  ".join(f"{root}/{'/'.join(key)}.jsonl" for key in sorted(results.missing))
        )


@entry_point
def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("root", nargs="?", type=Path, default=Path("outputs/eval"))
    parser.add_argument("--out", type=Path, default=Path("outputs/tables/vla"))
    parser.add_argument("--main", default="default", help="run of the per-skill and per-category tables")
    parser.add_argument("--split-run", default=SPLIT_RUN, help="run of the seen/unseen table")
    args = parser.parse_args()
    write_tables(args.root, args.out, args.main, args.split_run)


if __name__ == "__main__":
    main()

"""The paper's takeaways 4-6 tested on our evaluations: for each comparison a takeaway makes, our two success
rates, the change, how likely a change at least this large is by chance, the paper's two numbers, and whether
ours move the same way.

Two results files of the same episodes (one split: the same objects, rooms and seeds) are compared episode by
episode (exact McNemar test on the episodes both hold); files of different episodes (the seen/unseen splits
share neither objects nor rooms) by the two-proportion z-test. Rates here pool a file's episodes.
"""

from __future__ import annotations

from dataclasses import dataclass

from mobilemani_rl.utils.stats import mcnemar_p, two_proportion_p
from mobilemani_rl.utils.table_format import Table, num
from mobilemani_vla.eval.paper import (
    PROTOCOL_SPLIT,
    SEEN_SEEN,
    SEEN_UNSEEN,
    SPLIT_RUN,
    UNSEEN_SEEN,
    paper_success,
)

Result = tuple[str, str]  # (run, split) of a G1 results file


@dataclass(frozen=True)
class Comparison:
    takeaway: int
    label: str  # what the second result adds to or changes from the first
    first: Result
    second: Result


COMPARISONS = (
    Comparison(
        4,
        "head RGB, then + head depth",
        ("ablation_image_head_rgb", PROTOCOL_SPLIT),
        ("ablation_image_head_rgbd", PROTOCOL_SPLIT),
    ),
    Comparison(
        4,
        "head RGB, then + wrist RGB",
        ("ablation_image_head_rgb", PROTOCOL_SPLIT),
        ("ablation_image_head_wrist_rgb", PROTOCOL_SPLIT),
    ),
    Comparison(
        4,
        "head RGB-D, then + wrist RGB-D",
        ("ablation_image_head_rgbd", PROTOCOL_SPLIT),
        (SPLIT_RUN, PROTOCOL_SPLIT),
    ),
    Comparison(
        4,
        "head + wrist RGB, then + both depths",
        ("ablation_image_head_wrist_rgb", PROTOCOL_SPLIT),
        (SPLIT_RUN, PROTOCOL_SPLIT),
    ),
    Comparison(
        5, "no state, then + wrist pose", ("ablation_state_none", PROTOCOL_SPLIT), (SPLIT_RUN, PROTOCOL_SPLIT)
    ),
    Comparison(
        5,
        "wrist pose, then + grasp point",
        (SPLIT_RUN, PROTOCOL_SPLIT),
        ("ablation_state_grasp_point", PROTOCOL_SPLIT),
    ),
    Comparison(
        5,
        "+ grasp point, then + goal point",
        ("ablation_state_grasp_point", PROTOCOL_SPLIT),
        ("ablation_state_goal_point", PROTOCOL_SPLIT),
    ),
    Comparison(
        6, "seen objects and scenes, then unseen scenes", (SPLIT_RUN, SEEN_SEEN), (SPLIT_RUN, SEEN_UNSEEN)
    ),
    Comparison(
        6, "seen objects and scenes, then unseen objects", (SPLIT_RUN, SEEN_SEEN), (SPLIT_RUN, UNSEEN_SEEN)
    ),
    Comparison(
        6, "seen objects and scenes, then both unseen", (SPLIT_RUN, SEEN_SEEN), (SPLIT_RUN, PROTOCOL_SPLIT)
    ),
    Comparison(6, "unseen scenes, then unseen objects", (SPLIT_RUN, SEEN_UNSEEN), (SPLIT_RUN, UNSEEN_SEEN)),
    Comparison(6, "unseen objects, then both unseen", (SPLIT_RUN, UNSEEN_SEEN), (SPLIT_RUN, PROTOCOL_SPLIT)),
)


def episode_outcomes(records: list[dict]) -> dict[tuple, bool]:
    """Each episode's success by what makes it the same episode in another run: task, room, slot and seed."""
    return {
        (r["object_id"], r["skill"], r["scene"], r["episode"], r.get("seed")): bool(r["success"])
        for r in records
    }


@dataclass(frozen=True)
class Outcome:
    """Our side of one comparison."""

    successes: tuple[int, int]
    episodes: tuple[int, int]
    test: str  # how the p-value was computed, with its counts
    p: float

    @property
    def rates(self) -> tuple[float, float]:
        return self.successes[0] / self.episodes[0], self.successes[1] / self.episodes[1]


def compare(first: list[dict], second: list[dict]) -> Outcome:
    """Both files' pooled success and the test of their difference: paired on the episodes they share, else
    unpaired."""
    a, b = episode_outcomes(first), episode_outcomes(second)
    successes, episodes = (sum(a.values()), sum(b.values())), (len(a), len(b))
    if shared := a.keys() & b.keys():
        only_first = sum(a[k] and not b[k] for k in shared)
        only_second = sum(b[k] and not a[k] for k in shared)
        test = f"paired, {len(shared)} episodes: {only_first} vs {only_second} won by one only"
        return Outcome(successes, episodes, test, mcnemar_p(only_first, only_second))
    p = two_proportion_p(successes[0], episodes[0], successes[1], episodes[1])
    return Outcome(successes, episodes, "unpaired (different episodes)", p)


def direction(change: float) -> str:
    return "up" if change > 0 else "down" if change < 0 else "none"


def takeaway_row(results: dict, comparison: Comparison) -> list[str]:
    paper = [paper_success(*result) for result in (comparison.first, comparison.second)]
    found = [results.get(("g1", *result)) for result in (comparison.first, comparison.second)]
    head = [str(comparison.takeaway), comparison.label]
    paper_cells = [num(value) for value in paper]
    if not all(found):
        return [*head, "-", "-", "-", "-", "-", *paper_cells, "-"]
    outcome = compare(found[0]["records"], found[1]["records"])
    counts = zip(outcome.rates, outcome.successes, outcome.episodes, strict=True)
    ours = [f"{100 * r:.1f} ({k}/{n})" for r, k, n in counts]
    change = 100 * (outcome.rates[1] - outcome.rates[0])
    same = "-" if None in paper else "yes" if direction(change) == direction(paper[1] - paper[0]) else "no"
    p = "<0.001" if outcome.p < 0.001 else f"{outcome.p:.3f}"
    return [*head, *ours, f"{change:+.1f}", outcome.test, p, *paper_cells, same]


def takeaway_table(results: dict) -> Table:
    return Table(
        [
            "Takeaway",
            "Comparison",
            "First",
            "Second",
            "Change (points)",
            "Test",
            "p",
            "First (paper)",
            "Second (paper)",
            "Same direction",
        ],
        [takeaway_row(results, c) for c in COMPARISONS],
        "The paper's takeaways 4-6 on our G1 runs: success (%) pooled over each results file's episodes, "
        "and the two-sided p of the change (exact McNemar test on shared episodes, else the two-proportion "
        "z-test).",
    )

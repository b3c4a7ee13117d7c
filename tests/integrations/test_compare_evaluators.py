"""scripts.compare_evaluators: lerobot-eval's task ids paired with our harness's combinations, episode by
episode."""

import json

import pytest
from lerobot_env_mobilemanibench.tasks import task_combinations

from scripts.compare_evaluators import comparison_table, harness_episodes, lerobot_episodes

TASK = "g1/test/box/open/unseen_unseen"


def write_both(tmp_path, returns: dict[str, list[float]], harness_returns: dict[str, list[float]]):
    """An eval_info.json in lerobot-eval's layout and a harness .jsonl, successes where the return is > 0."""
    names = {c.name: c for c in task_combinations(TASK)}
    order = list(names)
    per_task = [
        {
            "task_group": TASK,
            "task_id": order.index(name),
            "metrics": {"sum_rewards": values, "successes": [v > 0 for v in values]},
        }
        for name, values in returns.items()
    ]
    info = tmp_path / "eval_info.json"
    info.write_text(json.dumps({"per_task": per_task}))
    records = [
        {
            "robot": "g1",
            "object_id": names[name].object_id,
            "skill": "open",
            "scene": names[name].scene,
            "episode": episode,
            "return": value,
            "success": value > 0,
        }
        for name, values in harness_returns.items()
        for episode, value in reversed(list(enumerate(values)))  # the file's order is not the episodes'
    ]
    harness = tmp_path / "harness.jsonl"
    harness.write_text("".join(json.dumps(r) + "\n" for r in records))
    return info, harness


def test_each_task_id_is_paired_with_its_combination_and_episode(tmp_path):
    first, second = [c.name for c in task_combinations(TASK)][:2]
    info, harness = write_both(
        tmp_path,
        {second: [1.0, -2.0], first: [-1.0, -3.0]},
        {first: [-1.0, -3.0], second: [1.0, 5.0]},
    )
    table = comparison_table(lerobot_episodes(info), {"ours": harness_episodes(harness)})
    rows = {line.split(" | ")[0].removeprefix("| "): line for line in table[2:]}
    assert rows[first] == f"| {first} | 0/2 | 0/2 (0.00) |"
    assert rows[second] == f"| {second} | 1/2 | 2/2 (7.00) |"
    assert rows["all"].startswith("| all | 25.0% (1/4;") and "| 50.0% (2/4;" in rows["all"]


def test_a_combination_with_other_episode_counts_is_named(tmp_path):
    first = task_combinations(TASK)[0].name
    info, harness = write_both(tmp_path, {first: [1.0, 2.0]}, {first: [1.0]})
    with pytest.raises(ValueError, match=f"{first}: lerobot-eval ran 2 episodes, the harness 1"):
        comparison_table(lerobot_episodes(info), {"ours": harness_episodes(harness)})

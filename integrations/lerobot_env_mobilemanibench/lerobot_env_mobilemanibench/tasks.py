"""`--env.task` strings -> the evaluation protocol's (object, skill, scene) combinations.

A task is `<robot>/<object id or category>/<skill>/<split>`, the split one of conf/eval/split (object split x
scene split, e.g. unseen_unseen: test objects in test rooms), e.g. `g1/test/box/open/unseen_unseen` or
`g1/laptop/open/seen_unseen`; several tasks are separated by commas. The combinations are the ones our harness
runs for the same subset (mobilemani_rl.envs.tasks.select_combinations), in its order.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from omegaconf import OmegaConf

from mobilemani_rl.assets.objects import CATEGORIES
from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.envs.tasks import Combination, SubsetCfg, select_combinations
from mobilemani_rl.utils.config_store import CONF_DIR, group_options
from mobilemani_rl.utils.errors import InputError, check_choice

TASK_FORMAT = "<robot>/<object id or category>/<skill>/<split>, e.g. g1/test/box/open/unseen_unseen"
SPLIT_GROUP = "eval/split"


def split_names() -> list[str]:
    return group_options(SPLIT_GROUP)


def task_subset(
    task: str, objects_per_category: int | None = None, scenes_per_object: int | None = None
) -> tuple[str, SubsetCfg]:
    """The robot and the harness's subset a task names."""
    parts = task.split("/")
    if len(parts) < 4 or not all(parts):
        raise InputError(f"env.task={task!r} is not {TASK_FORMAT}")
    robot, target, skill, split = parts[0], "/".join(parts[1:-2]), parts[-2], parts[-1]
    with named_task(task):
        check_choice(robot, ROBOTS, "robot")
        check_choice(split, split_names(), "split")
    splits = OmegaConf.to_container(OmegaConf.load(CONF_DIR / SPLIT_GROUP / f"{split}.yaml"))
    by_category = target in CATEGORIES
    subset = SubsetCfg(
        **splits,
        categories=[target] if by_category else None,
        objects=None if by_category else [target],
        objects_per_category=objects_per_category,
        skills=[skill],
        scenes_per_object=scenes_per_object,
    )
    return robot, subset


def task_combinations(
    task: str, objects_per_category: int | None = None, scenes_per_object: int | None = None
) -> list[Combination]:
    robot, subset = task_subset(task, objects_per_category, scenes_per_object)
    with named_task(task):
        return select_combinations(robot, subset)


@contextmanager
def named_task(task: str) -> Iterator[None]:
    """An unknown name in a task, reported with the task it came from."""
    try:
        yield
    except InputError as err:
        raise InputError(f"env.task={task!r}: {err}") from err


def split_tasks(tasks: str) -> list[str]:
    """The comma-separated tasks of `--env.task`, each once, in order."""
    names = list(dict.fromkeys(t.strip() for t in tasks.split(",") if t.strip()))
    if not names:
        raise InputError(f"env.task is empty; give one or more of {TASK_FORMAT}")
    return names

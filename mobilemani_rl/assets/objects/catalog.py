"""The object catalog: 631 ids `<category>/<index:04d>`, their train/test split, and the task table.

Counts follow the reference code's object lists (docs/reference.md, "Per-category constants"). Within a
category the train indices come first and the test indices after them (e.g. box 0-9 train, 10-13 test), except
holistic (YCB-like), whose first 18 entries are the test objects (as in the reference's YCB list). Each object
is generated from a numpy Generator seeded with the CRC32 of its id, so an id always yields the same model, in
any process.
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass

import numpy as np

from mobilemani_rl.assets.objects.categories import SKILLS_BY_KIND, ObjectKind
from mobilemani_rl.assets.objects.generators import GENERATORS
from mobilemani_rl.assets.objects.model import ObjectModel
from mobilemani_rl.utils.errors import check_choice

SPLIT_COUNTS: dict[str, tuple[int, int]] = {  # category: (train, test)
    "box": (10, 4),
    "toilet": (25, 5),
    "laptop": (30, 6),
    "trashcan": (30, 7),
    "dishwasher": (20, 5),
    "oven": (10, 2),
    "microwave": (3, 2),
    "refrigerator": (40, 12),
    "washing_machine": (10, 2),
    "car": (10, 2),
    "safe": (15, 4),
    "fridge": (8, 2),
    "cabinet": (20, 2),
    "window": (15, 3),
    "lever_door": (18, 4),
    "round_door": (20, 5),
    "faucet": (60, 18),
    "table": (90, 18),
    "cart": (12, 4),
    "holistic": (60, 18),
}
CATEGORIES = tuple(SPLIT_COUNTS)
SPLITS = ("train", "test")
TEST_FIRST = {"holistic"}
KIND_BY_CATEGORY = {"cart": ObjectKind.CART, "holistic": ObjectKind.RIGID}


def object_id(category: str, index: int) -> str:
    return f"{category}/{index:04d}"


def split_of(category: str, index: int) -> str:
    train, test = SPLIT_COUNTS[category]
    if category in TEST_FIRST:
        return "test" if index < test else "train"
    return "train" if index < train else "test"


def object_rng(oid: str) -> np.random.Generator:
    return np.random.default_rng(zlib.crc32(oid.encode()))


def make_object(category: str, index: int) -> ObjectModel:
    """Sample the object's design (cheap); its spec is only built when `build_spec` is called."""
    oid = object_id(category, index)
    design = GENERATORS[category](object_rng(oid))
    kind = KIND_BY_CATEGORY.get(category, ObjectKind.ARTICULATED)
    return ObjectModel(
        oid, category, kind, design.build, design.grasp_body, design.joint, split=split_of(category, index)
    )


def build_catalog() -> dict[str, ObjectModel]:
    return {
        obj.object_id: obj
        for category, (train, test) in SPLIT_COUNTS.items()
        for obj in (make_object(category, i) for i in range(train + test))
    }


CATALOG: dict[str, ObjectModel] = build_catalog()


def catalog_ids(category: str | None = None, split: str | None = None) -> list[str]:
    """Catalog ids, optionally of one category and/or split, in catalog order."""
    if category is not None:
        check_choice(category, CATEGORIES, "category")
    if split is not None:
        check_choice(split, SPLITS, "split")
    return [
        oid for oid, obj in CATALOG.items() if category in (None, obj.category) and split in (None, obj.split)
    ]


@dataclass(frozen=True)
class Task:
    robot: str
    object_id: str
    skill: str


def task_table(
    robots: tuple[str, ...] = ("g1", "xhand"), category: str | None = None, split: str | None = None
) -> list[Task]:
    """Every valid (robot, object, skill): open/close articulated, pull/push carts, pick holistic objects."""
    from mobilemani_rl.assets.robots import ROBOTS

    for robot in robots:
        check_choice(robot, ROBOTS, "robot")
    return [
        Task(robot, oid, skill)
        for robot in robots
        for oid in catalog_ids(category, split)
        for skill in SKILLS_BY_KIND[CATALOG[oid].kind]
    ]

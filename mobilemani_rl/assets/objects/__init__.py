"""Object registry: object id -> ObjectModel."""

from mobilemani_rl.assets.objects.catalog import CATALOG, CATEGORIES, SPLITS, Task, catalog_ids, task_table
from mobilemani_rl.assets.objects.categories import ALL_SKILLS, CATEGORY_PARAMS, ObjectKind, Place
from mobilemani_rl.assets.objects.handmade import TEST_OBJECTS
from mobilemani_rl.assets.objects.model import ObjectKinematics, ObjectModel
from mobilemani_rl.utils.errors import UnknownNameError, check_choice

OBJECTS: dict[str, ObjectModel] = {**TEST_OBJECTS, **CATALOG}


def object_choices() -> str:
    """The valid object ids, one span per category: the catalogue's hundreds of names would bury the error."""
    spans = [f"{ids[0]} to {ids[-1]}" for ids in map(catalog_ids, CATEGORIES)]
    return ", ".join([*spans, *TEST_OBJECTS])


def get_object(object_id: str) -> ObjectModel:
    if object_id not in OBJECTS:
        raise UnknownNameError(f"unknown object {object_id!r}; valid objects: {object_choices()}")
    return OBJECTS[object_id]


def check_skill(obj: ObjectModel, skill: str) -> str:
    """The skill, if the object supports it; otherwise one error naming the valid ones."""
    check_choice(skill, ALL_SKILLS, "skill")
    if skill not in obj.skills:
        raise UnknownNameError(
            f"skill {skill!r} does not apply to {obj.object_id} ({obj.kind}); "
            f"valid skills for it: {', '.join(obj.skills)}"
        )
    return skill


__all__ = [
    "CATALOG",
    "CATEGORIES",
    "CATEGORY_PARAMS",
    "OBJECTS",
    "SPLITS",
    "ObjectKind",
    "ObjectKinematics",
    "ObjectModel",
    "Place",
    "Task",
    "catalog_ids",
    "check_skill",
    "get_object",
    "object_choices",
    "task_table",
]

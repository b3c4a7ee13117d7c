"""The (object, skill, scene) task combinations a collection or an evaluation covers, and their instructions.

Shared by data collection (mobilemani_data) and closed-loop evaluation (mobilemani_vla), so both select tasks,
seed them and phrase them the same way.
"""

from __future__ import annotations

import zlib
from dataclasses import asdict, dataclass

from omegaconf import OmegaConf

from mobilemani_rl.assets.objects import ALL_SKILLS, CATEGORIES, SPLITS, catalog_ids, get_object
from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.assets.scenes import get_placement, placements_for
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.utils.errors import UnknownNameError, check_choice


@dataclass
class SubsetCfg:
    """Which (object, skill, scene) combinations to record, and how many successful episodes each."""

    split: str = "train"  # object split; explicit `objects` ignore it
    scene_split: str | None = None  # scene split (rooms 00–15 train, 16–19 test); None: same as `split`
    categories: list[str] | None = None  # None: all 20
    objects: list[str] | None = None  # explicit object ids; None: the catalog's objects of the split
    objects_per_category: int | None = None  # first k objects of each category; None: all
    skills: list[str] | None = None  # None: every skill of each object
    scenes: list[str] | None = None  # explicit scene ids (those of the object's setting are used)
    scenes_per_object: int | None = None  # first k scenes of the object's setting; None: all of the split
    episodes: int = 10  # successful episodes per combination, as the reference records


# As in the reference, the verb is the skill (carts already pull/push, rigid objects pick); the
# noun is the object's category with underscores as spaces, except that both door kinds are "door" and the
# YCB-like set, which has no per-object names here, is "object".
NOUNS = {"lever_door": "door", "round_door": "door", "holistic": "object"}


def instruction(skill: str, category: str) -> str:
    return f"{skill} {NOUNS.get(category, category.replace('_', ' '))}"


@dataclass(frozen=True)
class Combination:
    robot: str
    object_id: str
    category: str
    skill: str
    scene: str
    split: str  # the object's split ("none" for the hand-made test objects)
    scene_split: str

    @property
    def name(self) -> str:
        return f"{self.robot}/{self.object_id}/{self.skill}/{self.scene}"

    @property
    def instruction(self) -> str:
        return instruction(self.skill, self.category)

    def seed(self, base: int) -> int:
        """Env seed: the same combination and base seed always replay the same rollouts."""
        return (base * 1_000_003 + zlib.crc32(self.name.encode())) % 2**31

    def metadata(self) -> dict[str, str]:
        return asdict(self)


def _object_ids(subset: SubsetCfg) -> list[str]:
    if subset.objects:
        return [get_object(oid).object_id for oid in subset.objects]
    categories = subset.categories or list(CATEGORIES)
    ids: list[str] = []
    for category in categories:
        found = catalog_ids(category, subset.split)
        ids += found[: subset.objects_per_category] if subset.objects_per_category else found
    return ids


def select_combinations(robot: str, subset: SubsetCfg) -> list[Combination]:
    """Every requested combination in a stable order; stops with one message on unknown names."""
    check_choice(robot, ROBOTS, "robot")
    check_choice(subset.split, SPLITS, "split")
    scene_split = subset.scene_split or subset.split
    check_choice(scene_split, SPLITS, "scene split")
    for skill in subset.skills or ():
        check_choice(skill, ALL_SKILLS, "skill")
    wanted_scenes = [get_placement(s).scene_id for s in subset.scenes] if subset.scenes else None
    combos = []
    for oid in _object_ids(subset):
        obj = get_object(oid)
        skills = [s for s in obj.skills if subset.skills is None or s in subset.skills]
        scenes = [p.scene_id for p in placements_for(obj, scene_split)]
        if wanted_scenes is not None:
            scenes = [s for s in scenes if s in wanted_scenes]
        scenes = scenes[: subset.scenes_per_object] if subset.scenes_per_object else scenes
        combos += [
            Combination(robot, oid, obj.category, skill, scene, obj.split or "none", scene_split)
            for skill in skills
            for scene in scenes
        ]
    if not combos:
        raise UnknownNameError(f"nothing to run: {_why_empty(subset, scene_split)}")
    return combos


def _why_empty(subset: SubsetCfg, scene_split: str) -> str:
    """Which of the subset's keys left no combination, with what the selected objects do offer."""
    objects = [get_object(oid) for oid in _object_ids(subset)]
    more = f" and {len(objects) - 3} more" if len(objects) > 3 else ""
    named = f"the selected objects ({', '.join(o.object_id for o in objects[:3])}{more})"
    skills = sorted({s for o in objects for s in o.skills})
    if subset.skills is not None and not set(subset.skills) & set(skills):
        return f"subset.skills={subset.skills}, but {named} offer {', '.join(skills)}"
    scenes = sorted({p.scene_id for o in objects for p in placements_for(o, scene_split)})
    return f"subset.scenes={subset.scenes} names none of the scenes of {named}: {', '.join(scenes)}"


def recording_env_cfg(base: EnvCfg, task: TaskCfg, num_envs: int, seed: int) -> EnvCfg:
    """The env config one combination is recorded with: the base settings, its task, recording resets."""
    merged = OmegaConf.merge(
        OmegaConf.structured(base),
        {
            "task": OmegaConf.structured(task),
            "num_envs": num_envs,
            "seed": seed,
            "reset": {"recording": True},
        },
    )
    return OmegaConf.to_object(merged)

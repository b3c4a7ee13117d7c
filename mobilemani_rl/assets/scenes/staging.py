"""A `MobileManiEnv` inside a placement's room, built from the env's public pieces.

Until the env takes a scene id itself, this swaps the env's scene builder for one that calls `add_scene`, and
hands it an object whose stage top is the placement's support height (tabletop; reference §8b: lowered by
init_height, raised by the table height, recording zeroes the random height except for windows).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from unittest import mock

import mujoco

from mobilemani_rl.assets.objects import CATEGORY_PARAMS, ObjectModel, Place, get_object
from mobilemani_rl.assets.objects.categories import CategoryParams
from mobilemani_rl.assets.robots import RobotDescription
from mobilemani_rl.assets.scenes.compose import add_scene
from mobilemani_rl.assets.scenes.placements import Placement, get_placement
from mobilemani_rl.envs import mobilemani_env
from mobilemani_rl.envs.config import EnvCfg, PhysicsCfg
from mobilemani_rl.envs.scene import SceneIndex, build_scene_spec, index_scene


@dataclass(frozen=True)
class PlacedObject(ObjectModel):
    """An object whose scene parameters follow a placement (stage top on the placement's table)."""

    placement: Placement | None = None

    @property
    def params(self) -> CategoryParams:
        params = CATEGORY_PARAMS[self.category]
        if self.placement is None or self.placement.setting is not Place.TABLETOP:
            return params
        return dataclasses.replace(params, init_height=self.placement.support_height, random_height=False)


def place_object(obj: ObjectModel, placement: Placement) -> PlacedObject:
    fields = {f.name: getattr(obj, f.name) for f in dataclasses.fields(ObjectModel)}
    return PlacedObject(**fields, placement=placement)


def build_realistic_scene(
    robot: RobotDescription,
    obj: ObjectModel,
    physics: PhysicsCfg,
    placement: Placement,
    check_setting: bool = True,
) -> tuple[mujoco.MjModel, SceneIndex]:
    spec = build_scene_spec(robot, obj, physics)
    add_scene(spec, placement, obj, check_setting)
    model = spec.compile()
    return model, index_scene(model, robot, obj)


def realistic_env(cfg: EnvCfg, scene_id: str, check_setting: bool = True) -> mobilemani_env.MobileManiEnv:
    placement = get_placement(scene_id)
    obj = place_object(get_object(cfg.task.object), placement)

    def build(
        robot: RobotDescription,
        _obj: ObjectModel,
        physics: PhysicsCfg,
    ) -> tuple[mujoco.MjModel, SceneIndex]:
        return build_realistic_scene(robot, obj, physics, placement, check_setting)

    with (
        mock.patch.object(mobilemani_env, "get_object", lambda _id: obj),
        mock.patch.object(mobilemani_env, "build_scene", build),
    ):
        return mobilemani_env.MobileManiEnv(cfg)

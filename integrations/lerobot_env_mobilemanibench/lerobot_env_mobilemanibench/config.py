"""`--env.type=mobilemanibench`: LeRobot's env config for the benchmark.

`create_envs` returns `{task: {i: vector env of the task's i-th (object, skill, scene) combination}}`, the
combinations our harness evaluates for the same task and split (tasks.py); `lerobot-eval --eval.n_episodes=k`
then runs k episodes of every combination. The features are the exported dataset's: cameras `pixels/<camera>`
-> observation.images.<camera> at (observation_height, observation_width), `agent_pos` -> observation.state,
and the base-frame `action`. Defaults are the exporter's (mobilemani_data.config.ExportCfg); a dataset
exported otherwise (e.g. `make data PRESET=demo`: 64 px, head and wrist RGB) needs the same here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from lerobot.configs import FeatureType, PolicyFeature
from lerobot.envs.configs import EnvConfig
from lerobot.utils.constants import ACTION, OBS_IMAGES, OBS_STATE

from lerobot_env_mobilemanibench.tasks import split_tasks, task_combinations, task_subset
from lerobot_env_mobilemanibench.vector_env import (
    DEFAULT_CAMERAS,
    DEFAULT_SIZE,
    EPISODE_LENGTH,
    MobileManiBenchVectorEnv,
    check_observation,
)
from mobilemani_data import schema
from mobilemani_rl.assets.robots import get_robot
from mobilemani_rl.utils.errors import InputError


@EnvConfig.register_subclass("mobilemanibench")
@dataclass
class MobileManiBenchEnvConfig(EnvConfig):
    # <robot>/<object id or category>/<skill>/<split>[,<more tasks>] (tasks.py)
    task: str | None = "g1/test/box/open/unseen_unseen"
    fps: int = schema.FPS
    episode_length: int = EPISODE_LENGTH  # control steps
    cameras: list[str] = field(default_factory=lambda: list(DEFAULT_CAMERAS))  # head_rgb, wrist_depth, ...
    observation_height: int = DEFAULT_SIZE[0]
    observation_width: int = DEFAULT_SIZE[1]
    objects_per_category: int | None = None  # a category task: its first k objects (None: all)
    scenes_per_object: int | None = None  # each object's first k rooms of the split (None: all)
    action_convention: str = "conjugate"  # the dataset's base-frame action encoding (its export setting)

    def __post_init__(self) -> None:
        check_observation(
            tuple(self.cameras),
            self.observation_height,
            self.observation_width,
            self.action_convention,
            "env.",
        )
        robots = {task_subset(task)[0] for task in split_tasks(self.task or "")}
        if len(robots) != 1:
            raise InputError(f"env.task={self.task!r} names robots {sorted(robots)}; evaluate one at a time")
        robot = get_robot(robots.pop())
        image = (self.observation_height, self.observation_width, 3)
        self.features = {
            ACTION: PolicyFeature(type=FeatureType.ACTION, shape=(robot.action_dim,)),
            "agent_pos": PolicyFeature(
                type=FeatureType.STATE, shape=(schema.state_dim(len(robot.hand_joints)),)
            ),
            **{f"pixels/{c}": PolicyFeature(type=FeatureType.VISUAL, shape=image) for c in self.cameras},
        }
        self.features_map = {
            ACTION: ACTION,
            "agent_pos": OBS_STATE,
            **{f"pixels/{c}": f"{OBS_IMAGES}.{c}" for c in self.cameras},
        }

    @property
    def gym_kwargs(self) -> dict:
        return {
            "cameras": tuple(self.cameras),
            "observation_height": self.observation_height,
            "observation_width": self.observation_width,
            "episode_length": self.episode_length,
            "action_convention": self.action_convention,
        }

    def create_envs(
        self, n_envs: int, use_async_envs: bool = False
    ) -> dict[str, dict[int, MobileManiBenchVectorEnv]]:
        """One batched env per combination (MuJoCo steps the batch in its own threads, so `use_async_envs`
        changes nothing); each builds its scene at its first reset."""
        return {
            task: {
                i: MobileManiBenchVectorEnv(combo, n_envs, **self.gym_kwargs, prefix="env.")
                for i, combo in enumerate(
                    task_combinations(task, self.objects_per_category, self.scenes_per_object)
                )
            }
            for task in split_tasks(self.task or "")
        }

"""MobileManiBench episodes as a Gymnasium vector env, observed the way the exported dataset recorded them.

One batched env (mobilemani_rl.envs.MobileManiEnv) holds the whole vector, and the episode is our harness's:
the same env settings and batch seed (mobilemani_vla.eval.harness: `episode_env`, `batch_seed`), the same
first-episode accounting (mobilemani_rl.envs.rollout.FirstEpisodes) and the same observations
(mobilemani_vla.eval.observe.ObservationBuilder). So the episodes seeded s, s+1, ..., s+n-1 of an n-env vector
are episodes s .. s+n-1 of our harness run with `seed=s` and `episodes_per_batch=n`.

Observations follow LeRobot's env convention: `pixels` (camera name, e.g. head_rgb -> (H, W, 3) uint8) and
`agent_pos` (the dataset's `observation.state`), which `lerobot-eval` renames to `observation.images.<camera>`
and `observation.state`, the exported dataset's feature names. Actions are the dataset's `action` (base frame,
[-1, 1]). Each env runs one episode per reset: once it ends, the env stays done, its reward 0 and its
`is_success` the episode's (latched) success, as LeRobot's rollout and our harness both score it.
"""

from __future__ import annotations

from typing import Any, get_args

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode

from mobilemani_data import schema
from mobilemani_data.config import ExportCfg
from mobilemani_rl.assets.robots import get_robot
from mobilemani_rl.envs.base_frame import Convention, action_to_world
from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.rollout import FirstEpisodes
from mobilemani_rl.envs.tasks import Combination, SubsetCfg, select_combinations
from mobilemani_rl.utils.errors import InputError, check_choice
from mobilemani_vla.eval.harness import batch_seed, episode_env
from mobilemani_vla.eval.observe import ObservationBuilder

# The exporter's defaults, so that a policy trained on a default export runs unmodified.
_EXPORT = ExportCfg()
DEFAULT_CAMERAS = tuple(f"{c}_{m}" for c in _EXPORT.cameras for m in _EXPORT.modalities)
DEFAULT_SIZE = (_EXPORT.height, _EXPORT.width)
EPISODE_LENGTH = EnvCfg().episode_length


def image_key(camera: str) -> str:
    """'head_rgb' -> observation.images.head_rgb."""
    return schema.image_key(*camera.split("_"))


def check_observation(
    cameras: tuple[str, ...], height: int, width: int, convention: str, prefix: str = ""
) -> None:
    """The observation settings, each bad one named by its key (`prefix`: "env." in LeRobot's config)."""
    for camera in cameras:
        check_choice(camera, schema.IMAGE_STREAMS, f"{prefix}cameras entry")
    if len(set(cameras)) != len(cameras):
        raise InputError(f"{prefix}cameras={list(cameras)} names a camera twice")
    # LeRobot tells channels-last images by their channel axis being the shortest
    if min(height, width) <= 3:
        raise InputError(
            f"{prefix}observation_height={height}, {prefix}observation_width={width}: both must be >= 4"
        )
    check_choice(convention, get_args(Convention), f"{prefix}action_convention")


class MobileManiBenchVectorEnv(gym.vector.VectorEnv):
    metadata: dict[str, Any] = {
        "render_modes": ["rgb_array"],
        "render_fps": schema.FPS,
        "autoreset_mode": AutoresetMode.SAME_STEP,
    }
    render_mode = "rgb_array"  # render(): the first camera's images

    def __init__(
        self,
        combination: Combination,
        num_envs: int = 1,
        cameras: tuple[str, ...] = DEFAULT_CAMERAS,
        observation_height: int = DEFAULT_SIZE[0],
        observation_width: int = DEFAULT_SIZE[1],
        episode_length: int = EPISODE_LENGTH,
        action_convention: str = "conjugate",
        prefix: str = "",
    ) -> None:
        """`prefix` names the settings in errors as the caller's config does ("env." for LeRobot's)."""
        cameras, height, width = tuple(cameras), observation_height, observation_width
        check_observation(cameras, height, width, action_convention, prefix)
        if num_envs < 1 or episode_length < 1:
            raise InputError(
                f"num_envs={num_envs}, {prefix}episode_length={episode_length}: both must be >= 1"
            )
        self.combination, self.num_envs = combination, num_envs
        self.cameras, self.height, self.width = cameras, height, width
        self.convention = action_convention
        self.params = EnvCfg(episode_length=episode_length)  # the harness's settings otherwise
        robot = get_robot(combination.robot)
        pixels = {c: gym.spaces.Box(0, 255, (height, width, 3), np.uint8) for c in cameras}
        state = gym.spaces.Box(-np.inf, np.inf, (schema.state_dim(len(robot.hand_joints)),), np.float32)
        self.single_observation_space = gym.spaces.Dict(
            {"agent_pos": state, **({"pixels": gym.spaces.Dict(pixels)} if cameras else {})}
        )
        self.single_action_space = gym.spaces.Box(-1.0, 1.0, (robot.action_dim,), np.float32)
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, num_envs)
        # what LeRobot's rollout reads from every sub-env (env.call)
        self.task = self.task_description = combination.instruction
        self._max_episode_steps = episode_length
        self.episodes: FirstEpisodes | None = None  # the MuJoCo batch is built at the first reset
        self.builder: ObservationBuilder | None = None
        self.last_obs: dict | None = None

    def _build(self) -> None:
        # unseeded, a fresh env starts at episode 0 of seed 0
        env = episode_env(self.params, self.combination, self.num_envs, batch_seed(self.combination, 0))
        inputs = frozenset({image_key(c) for c in self.cameras} | {schema.STATE})
        self.builder = ObservationBuilder(env, inputs, self.task, self.width, self.height)
        self.episodes = FirstEpisodes(env)

    def first_episode(self, seed: int | list[int] | np.ndarray | None) -> int | None:
        """The number of the batch's first episode: reset(seed=s) numbers the envs' episodes s, s+1, ..."""
        if seed is None:
            return None
        seeds = [int(s) for s in np.atleast_1d(seed)]  # one int s stands for s, s+1, ...
        if len(seeds) == 1:
            seeds = list(range(seeds[0], seeds[0] + self.num_envs))
        if seeds != list(range(seeds[0], seeds[0] + self.num_envs)):
            raise InputError(
                f"reset(seed={seed}): a batch's episodes share one generator, so give its {self.num_envs} "
                "envs consecutive seeds s, s+1, ... (or one int s)"
            )
        return seeds[0]

    def reset(self, *, seed: int | list[int] | None = None, options: dict | None = None) -> tuple[dict, dict]:
        first = self.first_episode(seed)
        if self.episodes is None:
            self._build()
        self.episodes.reset(None if first is None else batch_seed(self.combination, first))
        return self._observe(), {"is_success": np.zeros(self.num_envs, dtype=bool)}

    def step(self, actions: np.ndarray) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray, dict]:
        if self.episodes is None:
            raise RuntimeError("call reset() before step()")
        env, running = self.episodes.env, self.episodes.running
        world = action_to_world(np.asarray(actions, np.float64), env.frames.base_quat, self.convention)
        result = self.episodes.step(world)
        still = self.episodes.running
        terminated = result.terminated & running
        info = {"is_success": np.where(still, result.success_flag, self.episodes.success)}
        reward = np.where(running, result.reward, 0.0)
        return self._observe(), reward, terminated, ~still & ~terminated, info

    def _observe(self) -> dict:
        obs = self.builder(self.episodes.running.copy())  # finished envs get black images, as in the harness
        self.last_obs = {"agent_pos": obs[schema.STATE].astype(np.float32)}
        if self.cameras:
            self.last_obs["pixels"] = {c: obs[image_key(c)] for c in self.cameras}
        return self.last_obs

    def render(self) -> np.ndarray:
        """Each env's first camera at the last step, (n, H, W, 3) uint8 (black without cameras)."""
        if self.last_obs is None or not self.cameras:
            return np.zeros((self.num_envs, self.height, self.width, 3), np.uint8)
        return self.last_obs["pixels"][self.cameras[0]]

    def call(self, name: str, *args: Any, **kwargs: Any) -> tuple:
        """Gymnasium's per-sub-env call: every env of the batch shares the task, its length and settings."""
        if name == "render":
            return tuple(self.render())
        value = getattr(self, name)
        return (value(*args, **kwargs) if callable(value) else value,) * self.num_envs

    def get_attr(self, name: str) -> tuple:
        return (getattr(self, name),) * self.num_envs

    def close_extras(self, **kwargs: Any) -> None:
        if self.builder is not None:
            self.builder.close()
        self.episodes = self.builder = self.last_obs = None


def make_combination(robot: str, object: str, skill: str, scene: str | None = None) -> Combination:
    """One combination by name; without a scene, the first unseen (test) room of the object's setting."""
    subset = SubsetCfg(
        split="test", objects=[object], skills=[skill], scenes=None if scene is None else [scene]
    )
    return select_combinations(robot, subset)[0]


def make_vector_env(
    num_envs: int = 1,
    robot: str = "g1",
    object: str = "test/box",
    skill: str = "open",
    scene: str | None = None,
    **observation: Any,
) -> MobileManiBenchVectorEnv:
    """What `gymnasium.make_vec("MobileManiBench/<robot>-v0", num_envs,
    vectorization_mode="vector_entry_point")` builds."""
    return MobileManiBenchVectorEnv(make_combination(robot, object, skill, scene), num_envs, **observation)


class MobileManiBenchEnv(gym.Env):
    """`gymnasium.make("MobileManiBench/<robot>-v0", object=..., skill=..., scene=...)`: a one-env vector with
    the batch axis removed."""

    metadata = MobileManiBenchVectorEnv.metadata

    def __init__(self, **kwargs: Any) -> None:
        self.vector = make_vector_env(1, **kwargs)
        self.observation_space = self.vector.single_observation_space
        self.action_space = self.vector.single_action_space
        self.task = self.task_description = self.vector.task

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[dict, dict]:
        obs, info = self.vector.reset(seed=seed, options=options)
        return _first(obs), _first(info)

    def step(self, action: np.ndarray) -> tuple[dict, float, bool, bool, dict]:
        obs, reward, terminated, truncated, info = self.vector.step(np.asarray(action)[None])
        return _first(obs), float(reward[0]), bool(terminated[0]), bool(truncated[0]), _first(info)

    def render(self) -> np.ndarray:
        return self.vector.render()[0]

    def close(self) -> None:
        self.vector.close()


def _first(batched: dict) -> dict:
    return {k: _first(v) if isinstance(v, dict) else v[0] for k, v in batched.items()}

"""Environment configuration dataclasses: EnvParamsCfg is conf/env's schema, TaskCfg the root's `task` block
(conf/robot and the RL root).

Defaults are the reference's (docs/reference.md) except for the MuJoCo
timestep, which is ours: see PhysicsCfg.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from omegaconf import DictConfig, OmegaConf

from mobilemani_rl.utils.errors import SEED_RULE, InputError, check_positive, check_values, is_seed


@dataclass
class PhysicsCfg:
    """Control runs at 30 Hz as the reference (60 Hz PhysX, decimation 2).

    MuJoCo takes `substeps` steps per control step (timestep = 1 / (control_hz * substeps)). 3 substeps
    (11.1 ms) is the largest setting at which the scripted grasps stay stable, measured with
    python -m scripts.physics_stability (docs/results/fidelity.md): at 2 substeps (16.7 ms, the reference's
    rate) contact penetration grows and the light can slips out of the pick. No setting produced NaNs or
    simulation errors. MuJoCo clamps contact time constants to
    twice the timestep, so larger steps mean softer contacts.
    """

    control_hz: float = 30.0
    substeps: int = 3
    solver_iterations: int = 20
    ls_iterations: int = 10
    nthread: int = 0  # 0: all cores

    @property
    def timestep(self) -> float:
        return 1.0 / (self.control_hz * self.substeps)


@dataclass
class TaskCfg:
    robot: str = "g1"
    object: str = "test/box"
    skill: str = "open"
    scene: str | None = None  # a placement id such as "tabletop/07"; None: the plain stage scene


@dataclass
class RobotChoiceCfg:
    """The robot group's block (conf/robot, `@package task`) in a root that takes no task."""

    robot: str = "g1"


@dataclass
class ActionCfg:
    pos_scale: float = 0.025  # m per step for a unit action
    rot_scale: float = 0.025  # rad per step for a unit action
    ik_damping: float = 0.01  # DLS lambda; the damping term is lambda^2 I


@dataclass
class ResetCfg:
    root_x_range: list[float] = field(default_factory=lambda: [-0.25, 0.25])
    root_y_range: list[float] = field(default_factory=lambda: [0.0, 0.5])  # only toward the object
    # [near, far] m in front of the grasp point along y, in place of the default root y + root_y_range: one
    # start distance for both robots (the fixed-base ablation's 0.5-1.0 m); None: the mobile start.
    root_y_distance_range: list[float] | None = None
    yaw_jitter_deg: float = 15.0
    random_height: float = 0.5  # stage height U(0, 0.5) m where the category allows it
    stage_shift: float = 0.1  # stage front face moved toward the robot by U(0, 0.1) m
    pick_yaw_deg: float = 90.0  # rigid objects spawn with yaw U(-90°, 90°)
    pick_y_offset: float = 0.1
    # Data recording, as in the reference: no stage shift and no random height
    # (windows keep theirs); room jitter on.
    recording: bool = False
    room_jitter_x: list[float] = field(default_factory=lambda: [-0.1, 0.1])
    room_jitter_y: list[float] = field(default_factory=lambda: [-0.05, 0.05])
    # Tabletop rooms: the table (and the object on it) raised or lowered per episode by U(-x, x) m from the
    # room's own height. With 16 train rooms each table height otherwise comes with one room's look, and a
    # policy learning from the pictures can take the height from the room instead of seeing it. 0: the room's
    # height, as the reference records.
    table_height_jitter: float = 0.0


@dataclass
class RewardWeights:
    """The reference's weights (docs/reference.md, "Reward terms"); identical for both robots."""

    diff_reach_pos_action: float = -0.1
    diff_reach_rot_action: float = -0.1
    diff_reach_joint_action: float = -0.1
    diff_reach_palm_rot_action: float = -0.1
    diff_hand_object: float = -1.0
    diff_hand_body_object: float = -0.0
    diff_hand_thumb_object: float = -0.0
    diff_hand_finger_object: float = -2.0
    diff_object_goal: float = -1.0
    bonus_grasp_object: float = 1.0
    diff_move_pos_action: float = -0.1
    diff_move_rot_action: float = -0.1
    bonus_object_goal: float = 2.0


@dataclass
class SuccessCfg:
    threshold: float = 0.05  # m, grasp point to goal
    hold_steps: int = 30  # truncate after this many (cumulative) success steps
    reach_radius: float = 0.2  # d_h at which reach terms switch off and grasping can count
    finger_radius: float = 0.1  # thumb and mean finger distance for the grasp flag
    max_hand_distance: float = 5.0  # termination
    max_speed: float = 10.0  # termination: palm or grasp point faster than this (m/s)


@dataclass
class EnvParamsCfg:
    """Everything of an env but its task: conf/env's schema (the task is the root's own `task` block)."""

    num_envs: int = 64
    episode_length: int = 300  # control steps (10 s at 30 Hz)
    # Lock the base's yaw and slide joints at their reset values: the IK moves the 7 arm joints alone (the
    # paper's fixed-base ablation, Table 8; conf/env/fixed_base.yaml).
    fixed_base: bool = False
    seed: int = 0
    obs_clip: float = 10.0
    reward_clip: float = 10.0
    physics: PhysicsCfg = field(default_factory=PhysicsCfg)
    actions: ActionCfg = field(default_factory=ActionCfg)
    reset: ResetCfg = field(default_factory=ResetCfg)
    rewards: RewardWeights = field(default_factory=RewardWeights)
    success: SuccessCfg = field(default_factory=SuccessCfg)

    def check(self) -> None:
        """Every value in its range, each failing one named by its key: a zero control rate divides by zero,
        a reversed reset range stops numpy mid-reset, and a zero success threshold or clip runs without a word
        but can never succeed or observe anything."""
        physics, actions, reset, success = self.physics, self.actions, self.reset, self.success
        check_positive(
            {
                "env.num_envs": self.num_envs,
                "env.episode_length": self.episode_length,
                "env.physics.substeps": physics.substeps,
                "env.physics.solver_iterations": physics.solver_iterations,
                "env.physics.ls_iterations": physics.ls_iterations,
                "env.success.hold_steps": success.hold_steps,
            }
        )
        above_zero = {
            "env.physics.control_hz": physics.control_hz,
            "env.obs_clip": self.obs_clip,
            "env.reward_clip": self.reward_clip,
            "env.actions.pos_scale": actions.pos_scale,
            "env.actions.rot_scale": actions.rot_scale,
            "env.success.threshold": success.threshold,
            "env.success.reach_radius": success.reach_radius,
            "env.success.finger_radius": success.finger_radius,
            "env.success.max_hand_distance": success.max_hand_distance,
            "env.success.max_speed": success.max_speed,
        }
        # a thread count (0: all cores), the IK damping, and spreads the resets draw as U(0, x) or U(-x, x)
        non_negative = {
            "env.physics.nthread": physics.nthread,
            "env.actions.ik_damping": actions.ik_damping,
            "env.reset.yaw_jitter_deg": reset.yaw_jitter_deg,
            "env.reset.random_height": reset.random_height,
            "env.reset.stage_shift": reset.stage_shift,
            "env.reset.pick_yaw_deg": reset.pick_yaw_deg,
            "env.reset.table_height_jitter": reset.table_height_jitter,
        }
        ranges = {
            "env.reset.root_x_range": reset.root_x_range,
            "env.reset.root_y_range": reset.root_y_range,
            "env.reset.room_jitter_x": reset.room_jitter_x,
            "env.reset.room_jitter_y": reset.room_jitter_y,
        }
        if reset.root_y_distance_range is not None:
            ranges["env.reset.root_y_distance_range"] = reset.root_y_distance_range
        check_values(
            [("env.seed", self.seed, is_seed(self.seed), SEED_RULE)]
            + [(key, value, value > 0, "above 0") for key, value in above_zero.items()]
            + [(key, value, value >= 0, ">= 0") for key, value in non_negative.items()]
            + [
                (key, list(pair), len(pair) == 2 and pair[0] <= pair[1], "[low, high] with low <= high")
                for key, pair in ranges.items()
            ]
        )
        if reset.root_y_distance_range is not None and reset.root_y_range != ResetCfg().root_y_range:
            raise InputError(
                f"env.reset.root_y_range={list(reset.root_y_range)} has no effect while "
                "env.reset.root_y_distance_range places the robot; set one of them"
            )


@dataclass
class EnvCfg(EnvParamsCfg):
    task: TaskCfg = field(default_factory=TaskCfg)

    def check(self) -> None:
        super().check()
        # a dict here would first fail as "'dict' object has no attribute 'robot'", naming no argument
        if not isinstance(self.task, TaskCfg):
            raise InputError(
                "EnvCfg(task=...) takes a TaskCfg(robot, object, skill, scene), "
                f"not a {type(self.task).__name__}"
            )


def check_env_block(env: EnvParamsCfg, set_by: dict[str, str]) -> None:
    """An entry point's env block: its values are in range, and the keys the entry point sets itself (e.g.
    env.num_envs from rl.ppo.num_envs) keep their defaults, since a value given there would be replaced
    without a word."""
    env.check()
    defaults = EnvParamsCfg()
    given = [
        f"env.{key}={getattr(env, key)} (set it through {owner})"
        for key, owner in set_by.items()
        if getattr(env, key) != getattr(defaults, key)
    ]
    if given:
        raise InputError(f"this entry point sets these env keys itself: {', '.join(given)}")


def with_env_task(cfg: DictConfig) -> dict[str, Any]:
    """A composed root as a dict whose `env` block holds the root's `task` block, as EnvCfg nests it."""
    plain = OmegaConf.to_container(cfg, resolve=True)
    plain["env"] = {**plain["env"], "task": plain.pop("task")}
    return plain

"""Sampling of episode starts as the reference does (docs/reference.md, "Robot placement at reset" and
"Objects"): robot pose, object placement, stage, joint, goal."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mobilemani_rl.assets.objects import ObjectKind, ObjectModel
from mobilemani_rl.assets.objects.model import CART_TRAVEL, PICK_LIFT
from mobilemani_rl.assets.robots import RobotDescription
from mobilemani_rl.assets.scenes import Placement
from mobilemani_rl.assets.stage import object_position, stage_position, stage_top
from mobilemani_rl.envs.config import ResetCfg
from mobilemani_rl.utils.rotations import quat_from_yaw

ROBOT_ROOT_Z = 0.01  # reference default root height
TOWARD_ROBOT = np.array([0.0, -1.0, 0.0])  # objects face -y; the robot stands there facing +y


@dataclass
class EpisodeStart:
    """Initial state for n envs."""

    root_pos: np.ndarray  # (n, 3) robot root (mocap)
    root_quat: np.ndarray  # (n, 4)
    stage_pos: np.ndarray  # (n, 3)
    object_pos: np.ndarray  # (n, 3) object root
    object_quat: np.ndarray  # (n, 4)
    joint_value: np.ndarray  # (n,) operated joint, zeros without one
    goal_pos: np.ndarray  # (n, 3)
    goal_scale: np.ndarray  # (n,) D0


def sample_episode_start(
    rng: np.random.Generator,
    n: int,
    robot: RobotDescription,
    obj: ObjectModel,
    skill: str,
    cfg: ResetCfg,
    placement: Placement | None = None,
) -> EpisodeStart:
    kin, params = obj.kinematics, obj.params
    # Recording and realistic rooms (the object stands on the placement's visible table) zero the random
    # height, except for windows, and the stage shift, as the reference records.
    plain = placement is None and not cfg.recording
    random_height = params.random_height and (plain or obj.category == "window")
    lift = rng.uniform(0.0, cfg.random_height, n) if random_height else np.zeros(n)
    top = stage_top(obj, placement) + lift
    stage_shift = cfg.stage_shift if plain else 0.0
    # The object's grasp point (at its initial joint value) sits over the env origin, as the reference.
    object_pos = object_position(obj, top, cfg.pick_y_offset)
    object_quat = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    joint_value = np.full(n, kin.init_value)
    if obj.kind is ObjectKind.RIGID:
        object_quat = quat_from_yaw(np.radians(rng.uniform(-cfg.pick_yaw_deg, cfg.pick_yaw_deg, n)))
    elif skill == "close":
        joint_value = rng.uniform(*kin.close_start_range(), n)
    grasp_start = object_pos + _rotate_z(object_quat, kin.handle_closed)
    goal_pos, goal_scale = _goal(obj, skill, object_pos, grasp_start, n)

    front = object_pos[:, 1] + kin.front_y - rng.uniform(0.0, stage_shift, n)
    stage_pos = stage_position(front, top)

    root_xy = np.asarray(robot.default_root_xy) + np.stack(
        (rng.uniform(*cfg.root_x_range, n), rng.uniform(*cfg.root_y_range, n)), axis=1
    )
    if skill == "close" and obj.kind is ObjectKind.ARTICULATED:
        # Back out of the door's sweep when opening moves the handle toward the robot, as the reference
        # does.
        sweep = kin.handle_opened[:2] - kin.handle_closed[:2]
        if sweep[1] < 0:
            root_xy = root_xy + sweep
    # Face the env origin (robot +y toward it), then jitter the yaw.
    yaw = np.arctan2(root_xy[:, 0], -root_xy[:, 1])
    yaw += np.radians(rng.uniform(-cfg.yaw_jitter_deg, cfg.yaw_jitter_deg, n))
    root_pos = np.concatenate((root_xy, np.full((n, 1), ROBOT_ROOT_Z)), axis=1)
    return EpisodeStart(
        root_pos, quat_from_yaw(yaw), stage_pos, object_pos, object_quat, joint_value, goal_pos, goal_scale
    )


def _rotate_z(quat: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Rotate an object-frame point by yaw-only quaternions."""
    yaw = 2.0 * np.arctan2(quat[:, 3], quat[:, 0])
    c, s = np.cos(yaw), np.sin(yaw)
    return np.stack(
        (c * point[0] - s * point[1], s * point[0] + c * point[1], np.full_like(c, point[2])), axis=1
    )


def _goal(
    obj: ObjectModel,
    skill: str,
    object_pos: np.ndarray,
    grasp_start: np.ndarray,
    n: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Goal points (docs/reference.md, "Goals") and the default goal distance D0."""
    kin = obj.kinematics
    if skill == "open":
        goal = object_pos + kin.handle_opened
    elif skill == "close":
        goal = object_pos + kin.handle_closed
    elif skill == "pick":
        goal = grasp_start + np.array([0.0, 0.0, PICK_LIFT])
    elif skill == "pull":
        goal = grasp_start + CART_TRAVEL * TOWARD_ROBOT
    else:  # push
        goal = grasp_start - CART_TRAVEL * TOWARD_ROBOT
    if obj.kind is ObjectKind.ARTICULATED:
        scale = kin.goal_distance
    else:
        scale = PICK_LIFT if skill == "pick" else CART_TRAVEL
    return goal, np.full(n, scale)

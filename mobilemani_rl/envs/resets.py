"""Sampling of episode starts as the reference does (docs/reference.md, "Robot placement at reset" and
"Objects"): robot pose, object placement, stage, joint, goal."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mobilemani_rl.assets.objects import ObjectKind, ObjectModel, Place
from mobilemani_rl.assets.objects.model import CART_TRAVEL, PICK_LIFT
from mobilemani_rl.assets.robots import RobotDescription
from mobilemani_rl.assets.robots.builder import BASE_RADIUS
from mobilemani_rl.assets.scenes import Placement
from mobilemani_rl.assets.stage import object_position, stage_position, stage_top
from mobilemani_rl.envs.config import ResetCfg
from mobilemani_rl.utils.errors import InputError
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
    table_offset: np.ndarray  # (n,) the table's height minus its room's (env.reset.table_height_jitter)


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
    plain = _plain(cfg, placement)
    random_height = params.random_height and (plain or obj.category == "window")
    lift = rng.uniform(0.0, cfg.random_height, n) if random_height else np.zeros(n)
    table_offset = np.zeros(n)
    if placement is not None and placement.setting is Place.TABLETOP and cfg.table_height_jitter > 0:
        table_offset = rng.uniform(-cfg.table_height_jitter, cfg.table_height_jitter, n)
    top = stage_top(obj, placement) + lift + table_offset
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

    root_xy = _root_xy(rng, n, robot, cfg)
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
        root_pos,
        quat_from_yaw(yaw),
        stage_pos,
        object_pos,
        object_quat,
        joint_value,
        goal_pos,
        goal_scale,
        table_offset,
    )


def _plain(cfg: ResetCfg, placement: Placement | None) -> bool:
    """Recording and realistic rooms (the object stands on the placement's visible table) zero the random
    height, except for windows, and the stage shift, as the reference records."""
    return placement is None and not cfg.recording


def _root_xy(rng: np.random.Generator, n: int, robot: RobotDescription, cfg: ResetCfg) -> np.ndarray:
    """(n, 2) robot roots: the default root plus the x and y offsets, or with root_y_distance_range that many
    metres in front of the grasp point (at the origin)."""
    x = robot.default_root_xy[0] + rng.uniform(*cfg.root_x_range, n)
    if cfg.root_y_distance_range is None:
        y = robot.default_root_xy[1] + rng.uniform(*cfg.root_y_range, n)
    else:
        y = -rng.uniform(*cfg.root_y_distance_range, n)
    return np.stack((x, y), axis=1)


def check_start_clearance(
    robot: RobotDescription, obj: ObjectModel, cfg: ResetCfg, placement: Placement | None = None
) -> None:
    """The nearest start keeps the base clear of the stage front (where the object's front face is): a
    start inside it would run, with the base stuck in the stage."""
    if cfg.root_y_distance_range is None:
        key, pair, nearest = "root_y_range", cfg.root_y_range, robot.default_root_xy[1] + cfg.root_y_range[1]
    else:
        key, pair = "root_y_distance_range", cfg.root_y_distance_range
        nearest = -pair[0]
    shift = cfg.stage_shift if _plain(cfg, placement) else 0.0
    front = object_position(obj, np.array(0.0), cfg.pick_y_offset)[1] + obj.kinematics.front_y - shift
    if nearest + BASE_RADIUS > front:
        raise InputError(
            f"env.reset.{key}={list(pair)} starts the {robot.name} base (radius {BASE_RADIUS} m) at y = "
            f"{nearest:.2f} m, inside the stage in front of {obj.object_id} (its front face as near as "
            f"y = {front:.2f} m); start the root at least {BASE_RADIUS - front:.2f} m in front of the grasp "
            "point"
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

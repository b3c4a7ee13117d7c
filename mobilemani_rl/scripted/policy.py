"""Scripted reference policy: follow the reward's reference actions with the privileged task state.

Phases per env: approach (pre-grasp point in front of the handle, then the grasp point; palm turned onto the
approach direction, hand open), close the hand, then move the grasp point toward the goal. It is the
sanity check that physics, IK and goals are consistent, and the simplest teacher. The open and closed hand
postures are the robot's default and grasp postures, except where its tuning replaces joints of them.

The reward's reference actions approach every handle along the grasp direction (0, 1, 0). Here the approach
comes from the handle's free side instead: every generated grip (bar, knob, lever, tab, lid edge, faucet
lever) faces -y of the object frame with its joint at 0, so its free side now is that direction turned by the
joint. For closed objects that is the grasp direction; for a lid standing 40-80° open it is
the lid's plane, where the fingers can straddle its edge. An arm that reaches low grips only with the palm
turned down (the G1's, on its fixed torso) approaches them from above at a pitch that grows with their depth.

A hinged link is moved along its circle rather than straight at the goal. A pull (open, pull, pick) needs the
grip: it speeds up gradually, keeps the palm where it closed on the link, and grasps again once the grip is
lost; a close or push goes on pushing with a hand that slipped off.
"""

from __future__ import annotations

import mujoco
import numpy as np

from mobilemani_rl.assets.objects import ObjectKind
from mobilemani_rl.assets.robots.scripted_tuning import ScriptedPolicyCfg
from mobilemani_rl.envs.mobilemani_env import PALM_ROTATION_TASKS, MobileManiEnv
from mobilemani_rl.envs.observations import normalize_to_limits
from mobilemani_rl.envs.rewards import GRASP_DIRECTION, palm_direction, rotation_onto, rotation_to
from mobilemani_rl.utils.rotations import (
    cross,
    quat_apply,
    quat_between_vectors,
    quat_conj,
    quat_from_matrix,
    quat_mul,
)

APPROACH, CLOSE, MOVE = 0, 1, 2
PULLING_SKILLS = {"open", "pull", "pick"}
LID_CATEGORIES = {"box", "laptop", "toilet", "trashcan"}  # gripped at a lid's free edge
VERTICAL_BAR_CATEGORIES = {"refrigerator"}  # the generators' only vertical handles
DOWN = np.array([0.0, 0.0, -1.0])
HAND_X = np.array([1.0, 0.0, 0.0])


def rotate_about(v: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rodrigues: rotate vectors v (n, 3) about unit axes (n, 3) by angles (n,)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return v * c + cross(axis, v) * s + axis * np.sum(axis * v, axis=1, keepdims=True) * (1.0 - c)


class ScriptedPolicy:
    def __init__(self, env: MobileManiEnv, cfg: ScriptedPolicyCfg | None = None) -> None:
        self.env = env
        self.cfg = cfg or env.robot.scripted
        n = env.num_envs
        self.phase = np.zeros(n, dtype=np.int64)
        self.phase_steps = np.zeros(n, dtype=np.int64)
        self.pregrasp_done = np.zeros(n, dtype=bool)
        # palm relative to the grip when the hand closed, in the link frame
        self.hold_offset = np.zeros((n, 3))
        idx = env.index
        self.follow = self.cfg.follow_handle and env.object.kind is ObjectKind.ARTICULATED
        # Rigid objects are picked from above: the arm cannot reach the centre of mass of an object low on the
        # table with the palm turned forward, and a lifting grasp holds best under the palm
        # (both robots pick the sampled catalog objects more often so than along the reward's grasp
        # direction).
        self.from_above = env.object.kind is ObjectKind.RIGID
        robot = env.robot
        self.hand_open = self.hand_action({**robot.default_qpos, **self.cfg.open_hand})
        self.hand_closed = self.hand_action(
            {**robot.grasp_hand_qpos, **(self.cfg.pick_hand if self.from_above else {})}
        )
        if self.cfg.push_lids_shut and env.object.category in LID_CATEGORIES and env.skill == "close":
            self.hand_closed = self.hand_open
        self.pregrasp_offset = self.cfg.pick_pregrasp_offset if self.from_above else self.cfg.pregrasp_offset
        # Where the palm point stops, per kind of grip: past the grip along the approach, toward the wrist.
        self.grasp_depth, self.grip_shift = self.cfg.grasp_depth, self.cfg.grip_shift
        if env.object.category in self.cfg.hooked_lips and env.skill == "open":
            self.grasp_depth, self.grip_shift = self.cfg.lip_hook_depth, self.cfg.lip_hook_shift
        elif env.object.category in LID_CATEGORIES:
            self.grip_shift = self.cfg.lid_grip_shift
        elif self.from_above:
            self.grasp_depth, self.grip_shift = self.cfg.pick_grasp_depth, self.cfg.pick_grip_shift
        # The reward's palm rotation (+90° about world y) turns the fingers across a vertical bar, so it
        # serves every task on one, not only the rewarded ones.
        self.palm_rotation = not self.from_above and (
            (env.object.category, env.skill) in PALM_ROTATION_TASKS
            or env.object.category in VERTICAL_BAR_CATEGORIES
        )
        # Only a held link follows a pull, so a pulling hand keeps its hold or grasps again; a hand that
        # slipped off a closing link still pushes it along.
        self.pulls = env.skill in PULLING_SKILLS
        self.slide = int(np.flatnonzero(~idx.ik_is_hinge)[0])  # the base slide's place in the IK chain
        self.joint_id = (
            int(np.flatnonzero(env.model.jnt_qposadr == idx.object_joint_qpos)[0])
            if idx.object_joint_qpos >= 0
            else -1
        )
        self.joint_is_hinge = (
            self.joint_id >= 0 and env.model.jnt_type[self.joint_id] == mujoco.mjtJoint.mjJNT_HINGE
        )

    def hand_action(self, posture: dict[str, float]) -> np.ndarray:
        """(nh,) hand action holding the hand joints at `posture` (joint name -> rad)."""
        env = self.env
        targets = np.array([posture[j] for j in env.robot.hand_joints])
        return np.clip(normalize_to_limits(targets, env.index.hand_limits), -1.0, 1.0)

    def approach_direction(self) -> np.ndarray:
        """(n, 3) unit direction from the grip's free side toward the surface it is mounted on."""
        env, n = self.env, self.env.num_envs
        if self.from_above:
            return np.broadcast_to(DOWN, (n, 3))
        if not self.follow:
            return self.tilted_down(np.broadcast_to(GRASP_DIRECTION, (n, 3)))
        v, idx = env.view, env.index
        direction = quat_apply(v.mocap_quat[:, idx.object_mocap], np.broadcast_to(GRASP_DIRECTION, (n, 3)))
        if self.joint_is_hinge:
            direction = rotate_about(direction, v.xaxis[:, self.joint_id], v.qpos[:, idx.object_joint_qpos])
        if not self.cfg.approach_from_below:
            direction[:, 2] = np.minimum(direction[:, 2], 0.0)
        norm = np.linalg.norm(direction, axis=1, keepdims=True)
        return self.tilted_down(np.where(norm > 0.3, direction / np.maximum(norm, 1e-9), GRASP_DIRECTION))

    def tilted_down(self, direction: np.ndarray) -> np.ndarray:
        """(n, 3) approach directions turned down about the horizontal axis across them, the more the lower
        the grip or its goal sits below `low_grip_height`. The goal counts because a hand that keeps the
        palm's pitch while moving (move_follow 0) must reach it with the pitch it grasped with: a dropping
        oven door takes its handle lower than where it was grasped."""
        cfg = self.cfg
        if cfg.low_grip_height is None:
            return direction
        lowest = np.minimum(self.env.frames.grasp_pos[:, 2], self.env.goal_pos[:, 2])
        tilt = np.clip(cfg.low_grip_tilt_rate * (cfg.low_grip_height - lowest), 0.0, cfg.low_grip_max_tilt)
        across = cross(direction, np.broadcast_to(-DOWN, direction.shape))
        norm = np.linalg.norm(across, axis=1, keepdims=True)
        # A vertical approach has no horizontal axis across it: it stays as it is.
        tilt = np.where(norm[:, 0] > 1e-3, tilt, 0.0)
        return rotate_about(direction, across / np.maximum(norm, 1e-9), -tilt)

    def face_rotation(self, approach: np.ndarray) -> np.ndarray:
        """(n, 3) RPY turning the palm onto the approach direction. With the palm rotation, the target is the
        reward's (the reset palm orientation rolled +90° about world y) turned the shortest way onto the
        approach, so that its roll stays about the approach direction when an open door turned the grip
        aside."""
        env, palm_quat = self.env, self.env.frames.palm_quat
        if self.from_above and self.cfg.pick_finger_yaw is not None:
            return self.top_down_rotation()
        if not self.palm_rotation:
            return rotation_to(palm_quat, approach)
        target = quat_mul(
            quat_between_vectors(palm_direction(env.palm_rot_target), approach), env.palm_rot_target
        )
        return rotation_onto(palm_quat, target)

    def top_down_rotation(self) -> np.ndarray:
        """(n, 3) RPY turning the palm down with the fingers (the hand frame's -x) `pick_finger_yaw` left of
        the robot's heading (its base's +y)."""
        f = self.env.frames
        heading = quat_apply(f.base_quat, np.broadcast_to(np.array([0.0, 1.0, 0.0]), (self.env.num_envs, 3)))
        fingers = rotate_about(
            heading, np.broadcast_to(-DOWN, heading.shape), np.full(len(heading), self.cfg.pick_finger_yaw)
        )
        fingers[:, 2] = 0.0
        fingers /= np.maximum(np.linalg.norm(fingers, axis=1, keepdims=True), 1e-9)
        down = np.broadcast_to(DOWN, fingers.shape)
        target = quat_from_matrix(np.stack([-fingers, cross(down, -fingers), down], axis=-1))
        return rotation_onto(f.palm_quat, target)

    def __call__(self) -> np.ndarray:
        self.env.require_reset()
        env, cfg, f = self.env, self.cfg, self.env.frames
        restarted = env.env_times == 0
        lost = (
            (self.phase == MOVE)
            & self.pulls
            & (np.linalg.norm(f.grasp_pos - f.palm_pos, axis=1) > cfg.regrasp_distance)
        )
        self._advance(restarted | lost, APPROACH)
        self.pregrasp_done[restarted | lost] = False

        n = env.num_envs
        actions = np.zeros((n, env.num_actions))
        actions[:, 6:] = self.hand_open
        approach = self.approach_direction()
        face_grip = self.face_rotation(approach)

        # Approach: pre-grasp point first, then straight in along the approach direction.
        pregrasp = f.grasp_pos - self.pregrasp_offset * approach
        near_pregrasp = np.linalg.norm(pregrasp - f.palm_pos, axis=1) < cfg.pregrasp_tolerance
        # Going in with the palm still turning would land a finger on a lid edge or a handle.
        aligned = np.sum(palm_direction(f.palm_quat) * approach, axis=1) > cfg.pregrasp_alignment
        self.pregrasp_done |= near_pregrasp & aligned & (self.phase == APPROACH)
        grasp_target = (
            f.grasp_pos + self.grasp_depth * approach + self.grip_shift * quat_apply(f.palm_quat, HAND_X)
        )
        target = np.where(self.pregrasp_done[:, None], grasp_target, pregrasp)
        actions[:, 0:3] = np.clip(cfg.pos_gain * (target - f.palm_pos), -1.0, 1.0)
        if self.from_above and cfg.pick_descent_while_moving is not None:
            # The IK makes up for the descending arm's swing back toward the shoulder with the base, which
            # lags: a fast descent lands the palm behind a low object, whose back the fingers then push away.
            waiting = self.pregrasp_done & (np.abs(f.joint_vel[:, self.slide]) > cfg.base_moving_speed)
            actions[waiting, 2] = np.maximum(actions[waiting, 2], -cfg.pick_descent_while_moving)
        actions[:, 3:6] = np.clip(cfg.rot_gain * face_grip, -1.0, 1.0)
        gap = np.linalg.norm(grasp_target - f.palm_pos, axis=1)
        # Blocked: no longer closing in on the grip, also where the palm pushes a free link ahead of it.
        blocked = (gap < cfg.blocked_radius) & (
            np.linalg.norm(f.palm_linvel - f.grasp_linvel, axis=1) < cfg.blocked_speed
        )
        reached = self.pregrasp_done & ((gap < cfg.grasp_tolerance) | blocked)
        self._advance(reached & (self.phase == APPROACH), CLOSE)

        holding = self.phase >= CLOSE
        actions[holding, 6:] = self.hand_closed
        closing = self.phase == CLOSE
        actions[closing, 0:6] = 0.0
        closed = closing & (self.phase_steps >= cfg.close_steps)
        self.hold_offset[closed] = quat_apply(
            quat_conj(f.grasp_quat[closed]), (f.palm_pos - f.grasp_pos)[closed]
        )
        self._advance(closed, MOVE)

        moving = self.phase == MOVE
        to_goal = env.goal_pos - f.grasp_pos
        move = self.move_action(to_goal)
        if self.pulls:
            speed = np.minimum(1.0, (self.phase_steps[:, None] + 1) / cfg.move_ramp_steps)
            move = np.clip(move, -speed, speed)
            # Keep the palm where it closed on the link:
            # a slip along the handle is pulled back instead of growing.
            slip = f.grasp_pos + quat_apply(f.grasp_quat, self.hold_offset) - f.palm_pos
            move += cfg.hold_gain * cfg.pos_gain * slip
        away = -to_goal / np.maximum(np.linalg.norm(to_goal, axis=1, keepdims=True), 1e-9)
        turn = cfg.move_rotation * rotation_to(f.palm_quat, away) + cfg.move_follow * face_grip
        actions[moving, 0:3] = np.clip(move[moving], -1.0, 1.0)
        actions[moving, 3:6] = np.clip(cfg.rot_gain * turn[moving], -1.0, 1.0)
        self.phase_steps += 1
        return actions

    def move_action(self, to_goal: np.ndarray) -> np.ndarray:
        """(n, 3) position action moving the grip by to_goal (goal minus grip). A hinged grip moves along its
        circle (the goal lies on it: both are the same point of the link), toward a point `arc_lead` ahead, by
        the arc length left: pulling along the chord would drag the grip out of the hand."""
        env, f, cfg = self.env, self.env.frames, self.cfg
        if not (self.joint_is_hinge and cfg.arc_lead > 0.0):
            return cfg.pos_gain * to_goal
        anchor, axis = env.view.xanchor[:, self.joint_id], env.view.xaxis[:, self.joint_id]
        radial = f.grasp_pos - anchor
        across, across_goal = (
            p - axis * np.sum(axis * p, axis=1, keepdims=True) for p in (radial, env.goal_pos - anchor)
        )
        angle = np.arctan2(
            np.sum(axis * cross(across, across_goal), axis=1), np.sum(across * across_goal, axis=1)
        )
        radius = np.maximum(np.linalg.norm(across, axis=1), 1e-3)
        lead = cfg.arc_lead / radius
        ahead = rotate_about(radial, axis, np.clip(angle, -lead, lead)) - radial
        unit = ahead / np.maximum(np.linalg.norm(ahead, axis=1, keepdims=True), 1e-9)
        return unit * (cfg.pos_gain * np.abs(angle) * radius)[:, None]

    def _advance(self, mask: np.ndarray, phase: int) -> None:
        self.phase[mask] = phase
        self.phase_steps[mask] = 0

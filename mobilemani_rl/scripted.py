"""Scripted reference policy: follow the reward's reference actions with the privileged task state.

Phases per env: approach (pre-grasp point in front of the handle, then the grasp point; palm turned onto the
approach direction, hand at its default), close the hand, then move the grasp point toward the goal. It is the
sanity check that physics, IK and goals are consistent, and the simplest teacher.

The reward's reference actions approach every handle along the grasp direction (0, 1, 0). Here the approach
comes from the handle's free side instead: every generated grip (bar, knob, lever, tab, lid edge, faucet
lever) faces -y of the object frame with its joint at 0, so its free side now is that direction turned by the
joint. For closed objects that is the grasp direction; for a lid standing 40-80° open it is
the lid's plane, where the fingers can straddle its edge.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mobilemani_rl.assets.objects import ObjectKind
from mobilemani_rl.envs.mobilemani_env import PALM_ROTATION_TASKS, MobileManiEnv
from mobilemani_rl.envs.observations import normalize_to_limits
from mobilemani_rl.envs.rewards import GRASP_DIRECTION, palm_direction, rotation_to
from mobilemani_rl.rotations import cross, euler_from_quat, quat_apply, quat_conj, quat_mul

APPROACH, CLOSE, MOVE = 0, 1, 2
DOWN = np.array([0.0, 0.0, -1.0])


@dataclass
class ScriptedPolicyCfg:
    pos_gain: float = 12.0  # action per metre of error (saturates at 1 = 2.5 cm per step)
    rot_gain: float = 4.0
    pregrasp_offset: float = 0.08  # m in front of the grasp point along the approach direction
    pick_pregrasp_offset: float = 0.15  # above a rigid object's centre of mass: clears tall objects
    pregrasp_tolerance: float = 0.015
    pregrasp_alignment: float = 0.985  # cosine between palm and approach directions needed to go in (~10°)
    grasp_depth: float = 0.0  # m past the grasp point (along the approach direction) where the palm point stops
    grasp_tolerance: float = 0.012
    blocked_radius: float = 0.05  # the palm stopped this close to the grasp point (touching the object): close
    blocked_speed: float = 0.01  # m/s
    close_steps: int = 8
    follow_handle: bool = True  # approach from the grip's free side (else along the grasp direction)
    approach_from_below: bool = True  # else a grip facing down (under a dropped door) is approached horizontally
    move_follow: float = 1.0  # weight of keeping the palm on the grip's free side while moving
    move_rotation: float = 0.0  # weight of the reward's palm-rotation target while moving (it fights the grasp)


# The five-finger hand stops with the handle a little deeper, nearer its palm face, so that the curled fingers
# pass behind the handle, and its weak finger servos need longer to close than the parallel gripper. The
# gripper's pads let a turning handle rotate between them, while turning the wrist with it makes them slip.
# Turning the gripper up under a dropped oven door throws the G1 arm into the door, while its fingers pinch the
# hanging handle from the front as well; the hand's wrist would hit the door from the front.
ROBOT_CFG = {"g1": ScriptedPolicyCfg(move_follow=0.0, approach_from_below=False),
             "xhand": ScriptedPolicyCfg(grasp_depth=0.012, close_steps=15)}


def rotate_about(v: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rodrigues: rotate vectors v (n, 3) about unit axes (n, 3) by angles (n,)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return v * c + cross(axis, v) * s + axis * np.sum(axis * v, axis=1, keepdims=True) * (1.0 - c)


class ScriptedPolicy:
    def __init__(self, env: MobileManiEnv, cfg: ScriptedPolicyCfg | None = None) -> None:
        self.env = env
        self.cfg = cfg or ROBOT_CFG[env.robot.name]
        n = env.num_envs
        self.phase = np.zeros(n, dtype=np.int64)
        self.phase_steps = np.zeros(n, dtype=np.int64)
        self.pregrasp_done = np.zeros(n, dtype=bool)
        self.palm_rotation = (env.object.category, env.skill) in PALM_ROTATION_TASKS
        grasp = np.array([env.robot.grasp_hand_qpos[j] for j in env.robot.hand_joints])
        self.hand_closed = normalize_to_limits(grasp, env.index.hand_limits)
        idx = env.index
        self.follow = self.cfg.follow_handle and env.object.kind is ObjectKind.ARTICULATED
        # Rigid objects are picked from above: the arm cannot reach the centre of mass of an object low on the
        # table with the palm turned forward, and a lifting grasp holds best under the palm.
        self.from_above = env.object.kind is ObjectKind.RIGID
        self.pregrasp_offset = self.cfg.pick_pregrasp_offset if self.from_above else self.cfg.pregrasp_offset
        self.joint_id = int(np.flatnonzero(env.model.jnt_qposadr == idx.object_joint_qpos)[0]) \
            if idx.object_joint_qpos >= 0 else -1
        self.joint_is_hinge = self.joint_id >= 0 and \
            env.model.jnt_type[self.joint_id] == mujoco.mjtJoint.mjJNT_HINGE

    def approach_direction(self) -> np.ndarray:
        """(n, 3) unit direction from the grip's free side toward the surface it is mounted on."""
        env, n = self.env, self.env.num_envs
        if self.from_above:
            return np.broadcast_to(DOWN, (n, 3))
        if not self.follow:
            return np.broadcast_to(GRASP_DIRECTION, (n, 3))
        v, idx = env.view, env.index
        direction = quat_apply(v.mocap_quat[:, idx.object_mocap], np.broadcast_to(GRASP_DIRECTION, (n, 3)))
        if self.joint_is_hinge:
            direction = rotate_about(direction, v.xaxis[:, self.joint_id], v.qpos[:, idx.object_joint_qpos])
        if not self.cfg.approach_from_below:
            direction[:, 2] = np.minimum(direction[:, 2], 0.0)
        norm = np.linalg.norm(direction, axis=1, keepdims=True)
        return np.where(norm > 0.3, direction / np.maximum(norm, 1e-9), GRASP_DIRECTION)

    def __call__(self) -> np.ndarray:
        env, cfg, f = self.env, self.cfg, self.env.frames
        restarted = env.env_times == 0
        self.phase[restarted] = APPROACH
        self.phase_steps[restarted] = 0
        self.pregrasp_done[restarted] = False

        n = env.num_envs
        actions = np.zeros((n, env.num_actions))
        hand_open = np.clip(env.default_hand_action, -1.0, 1.0)
        actions[:, 6:] = hand_open
        approach = self.approach_direction()
        face_grip = rotation_to(f.palm_quat, approach)

        # Approach: pre-grasp point first, then straight in along the approach direction.
        pregrasp = f.grasp_pos - self.pregrasp_offset * approach
        near_pregrasp = np.linalg.norm(pregrasp - f.palm_pos, axis=1) < cfg.pregrasp_tolerance
        # Going in with the palm still turning would land a finger on a lid edge or a handle.
        aligned = np.sum(palm_direction(f.palm_quat) * approach, axis=1) > cfg.pregrasp_alignment
        self.pregrasp_done |= near_pregrasp & aligned & (self.phase == APPROACH)
        grasp_target = f.grasp_pos + cfg.grasp_depth * approach
        target = np.where(self.pregrasp_done[:, None], grasp_target, pregrasp)
        actions[:, 0:3] = np.clip(cfg.pos_gain * (target - f.palm_pos), -1.0, 1.0)
        actions[:, 3:6] = np.clip(cfg.rot_gain * face_grip, -1.0, 1.0)
        if self.palm_rotation and not self.from_above:
            pitch = euler_from_quat(quat_mul(env.palm_rot_target, quat_conj(f.palm_quat)))[:, 1]
            actions[:, 4] = np.clip(cfg.rot_gain * pitch, -1.0, 1.0)
        gap = np.linalg.norm(grasp_target - f.palm_pos, axis=1)
        blocked = (gap < cfg.blocked_radius) & (np.linalg.norm(f.palm_linvel, axis=1) < cfg.blocked_speed)
        reached = self.pregrasp_done & ((gap < cfg.grasp_tolerance) | blocked)
        self._advance(reached & (self.phase == APPROACH), CLOSE)

        holding = self.phase >= CLOSE
        actions[holding, 6:] = self.hand_closed
        closing = self.phase == CLOSE
        actions[closing, 0:6] = 0.0
        self._advance(closing & (self.phase_steps >= cfg.close_steps), MOVE)

        moving = self.phase == MOVE
        to_goal = env.goal_pos - f.grasp_pos
        move = np.clip(cfg.pos_gain * to_goal, -1.0, 1.0)
        away = -to_goal / np.maximum(np.linalg.norm(to_goal, axis=1, keepdims=True), 1e-9)
        turn = cfg.move_rotation * rotation_to(f.palm_quat, away) + cfg.move_follow * face_grip
        actions[moving, 0:3] = move[moving]
        actions[moving, 3:6] = np.clip(cfg.rot_gain * turn[moving], -1.0, 1.0)
        self.phase_steps += 1
        return actions

    def _advance(self, mask: np.ndarray, phase: int) -> None:
        self.phase[mask] = phase
        self.phase_steps[mask] = 0

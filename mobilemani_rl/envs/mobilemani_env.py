"""The batched MobileManiRL environment: N MuJoCo simulations in one `mujoco.batch.Batch`.

Step order follows the reference DirectRLEnv: action → IK → physics substeps → counters
→ dones → rewards → resets → observations. Everything above physics is vectorised numpy over envs.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import mujoco.batch
import numpy as np

from mobilemani_rl.assets.objects import ObjectKind, check_skill, get_object
from mobilemani_rl.assets.robots import get_robot
from mobilemani_rl.assets.scenes import (
    ROOM_BODY,
    TABLE_BODY,
    RoomJitterCfg,
    get_placement,
    sample_room_offsets,
)
from mobilemani_rl.envs.actions import checked_actions
from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.frames import FrameReader, Frames, SimView
from mobilemani_rl.envs.ik import chain_jacobian, dls_step, wrist_pose_error
from mobilemani_rl.envs.observations import compute_observation, normalize_to_limits, observation_dim
from mobilemani_rl.envs.resets import check_start_clearance, sample_episode_start
from mobilemani_rl.envs.rewards import RewardContext, TaskDistances, grasp_flag, reward_terms, total_reward
from mobilemani_rl.envs.scene import build_scene, ik_joints
from mobilemani_rl.envs.terminations import hand_too_far_or_too_fast, time_out_or_held_success
from mobilemani_rl.utils.errors import SEED_RULE, InputError, is_seed
from mobilemani_rl.utils.rotations import quat_from_euler, quat_mul

# The palm-rotation reach term is on only for these (category, skill) pairs, as in the reference.
PALM_ROTATION_TASKS = {("holistic", "pick"), ("refrigerator", "open")}
PALM_ROTATION_PRE = quat_from_euler(np.array([0.0, np.pi / 2, 0.0]))  # +90° about world y


def mocap_id(model: mujoco.MjModel, body: str) -> int:
    """The named body's mocap index, -1 where the model has no such body (a scene without a room or table)."""
    found = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
    return -1 if found < 0 else int(model.body_mocapid[found])


@dataclass
class StepResult:
    obs: np.ndarray  # (n, obs_dim) float32
    reward: np.ndarray  # (n,)
    terminated: np.ndarray  # (n,) bool, failures
    truncated: np.ndarray  # (n,) bool, time-outs and success holds (value is bootstrapped)
    success_flag: np.ndarray  # (n,) bool, latched success of the episode that ran this step (before resets)
    final_obs: np.ndarray  # (len(done_ids), obs_dim) last observation of each episode that ended this step
    done_ids: np.ndarray  # envs whose episode ended this step (they were reset; `obs` is their first one)
    reward_terms: dict[str, np.ndarray]  # weighted reward terms per env
    log: dict[str, float | np.ndarray]
    nan_actions: np.ndarray  # (n,) int, NaN action entries this step (applied as 0)


class MobileManiEnv:
    """Batched env for one (robot, object, skill) task."""

    def __init__(self, cfg: EnvCfg) -> None:
        # before MuJoCo sees the values: its own messages ("nsim must be positive") name no key
        cfg.check()
        self.cfg = cfg
        self.robot = get_robot(cfg.task.robot)
        self.object = get_object(cfg.task.object)
        self.skill = check_skill(self.object, cfg.task.skill)
        self.placement = get_placement(cfg.task.scene) if cfg.task.scene else None
        check_start_clearance(self.robot, self.object, cfg.reset, self.placement)
        self.model, self.index = build_scene(self.robot, self.object, cfg.physics, cfg.reset, self.placement)
        self.room_mocap, self.table_mocap = (mocap_id(self.model, body) for body in (ROOM_BODY, TABLE_BODY))
        self.num_envs = cfg.num_envs
        self.num_actions = self.robot.action_dim
        self.max_episode_length = cfg.episode_length
        self.batch = mujoco.batch.Batch(
            self.model, cfg.num_envs, nthread=cfg.physics.nthread, persistent=True
        )
        self.view = SimView(self.batch, self.model)
        self.frame_reader = FrameReader(self.view, self.index)
        self.rng = np.random.default_rng(cfg.seed)
        self.all_ids = np.arange(self.num_envs)
        idx = self.index
        self.joint_limits = np.concatenate((idx.ik_limits, idx.hand_limits))
        default = dict(zip(idx.robot_qpos.tolist(), idx.robot_default_qpos.tolist(), strict=True))
        self.default_hand_action = normalize_to_limits(
            np.array([default[q] for q in idx.hand_qpos]), idx.hand_limits
        )
        self.ik = ik_joints(idx, cfg.fixed_base)
        # A locked base stays at the reset values, the robot's defaults.
        self.base_qpos, self.base_dof = idx.ik_qpos[idx.ik_is_base], idx.ik_dof[idx.ik_is_base]
        self.base_value = np.array([default[q] for q in self.base_qpos])
        self.num_obs = observation_dim(
            self.num_actions, len(idx.finger_sites), len(idx.active_bodies), len(self.joint_limits)
        )
        self.use_palm_rotation = (self.object.category, self.skill) in PALM_ROTATION_TASKS
        n = self.num_envs
        self.episode_length_buf = np.zeros(n, dtype=np.int64)  # may be randomised by a trainer
        self.env_times = np.zeros(n, dtype=np.int64)  # drives the time encoding; always starts at 0
        self.success_count = np.zeros(n, dtype=np.int64)
        self.success_flag = np.zeros(n, dtype=bool)
        self.last_action = np.zeros((n, self.num_actions))
        self.goal_pos = np.zeros((n, 3))
        self.goal_scale = np.ones(n)
        self.palm_rot_target = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
        self.frames: Frames | None = None
        self.task_distances: TaskDistances | None = None
        self.obs: np.ndarray | None = None

    # ------------------------------------------------------------------ reset
    def reset(self, seed: int | None = None) -> np.ndarray:
        if seed is not None:
            if not is_seed(seed):
                raise InputError(f"reset(seed={seed!r}): the seed must be {SEED_RULE}, or None")
            self.rng = np.random.default_rng(seed)
        self.batch.reset(stage=mujoco.mjtStage.mjSTAGE_NONE)
        self.frames = self.task_distances = None
        self._reset_envs(self.all_ids)
        self.obs = self._observe()
        return self.obs

    def _reset_envs(self, ids: np.ndarray) -> None:
        idx, v = self.index, self.view
        start = sample_episode_start(
            self.rng, len(ids), self.robot, self.object, self.skill, self.cfg.reset, self.placement
        )
        rows = ids[:, None]
        v.qpos[rows, idx.robot_qpos] = idx.robot_default_qpos
        v.qvel[ids] = 0.0
        v.ctrl[rows, idx.robot_act] = v.qpos[rows, idx.robot_act_qpos]
        v.mocap_pos[ids, idx.robot_mocap] = start.root_pos
        v.mocap_quat[ids, idx.robot_mocap] = start.root_quat
        v.mocap_pos[ids, idx.stage_mocap] = start.stage_pos
        if self.object.kind is ObjectKind.ARTICULATED:
            v.mocap_pos[ids, idx.object_mocap] = start.object_pos
            v.mocap_quat[ids, idx.object_mocap] = start.object_quat
        else:
            q = idx.object_free_qpos
            v.qpos[ids, q : q + 3] = start.object_pos
            v.qpos[ids, q + 3 : q + 7] = start.object_quat
        if idx.object_joint_qpos >= 0:
            v.qpos[ids, idx.object_joint_qpos] = start.joint_value
        if self.room_mocap >= 0:
            rcfg = self.cfg.reset
            jitter = RoomJitterCfg(tuple(rcfg.room_jitter_x), tuple(rcfg.room_jitter_y))
            offsets = sample_room_offsets(self.rng, len(ids), jitter)
            v.mocap_pos[ids, self.room_mocap] = self.model.body_pos[self.model.body(ROOM_BODY).id] + offsets
            if self.table_mocap >= 0:  # the table goes with the room, at the episode's height
                offsets[:, 2] += start.table_offset
                v.mocap_pos[ids, self.table_mocap] = (
                    self.model.body_pos[self.model.body(TABLE_BODY).id] + offsets
                )
        self.batch.forward(ids, stage=mujoco.mjtStage.mjSTAGE_VEL)
        fresh = self.frame_reader.read(ids)
        self.goal_pos[ids] = start.goal_pos
        distances = TaskDistances.measure(fresh, start.goal_pos)
        if self.frames is None:
            self.frames, self.task_distances = fresh, distances
        else:
            self.frames.assign(ids, fresh)
            self.task_distances.assign(ids, distances)
        self.goal_scale[ids] = start.goal_scale
        self.palm_rot_target[ids] = quat_mul(PALM_ROTATION_PRE, fresh.palm_quat)
        self.episode_length_buf[ids] = 0
        self.env_times[ids] = 0
        self.success_count[ids] = 0
        self.success_flag[ids] = False
        self.last_action[ids] = 0.0

    def require_reset(self) -> None:
        """Before the first reset nothing has been measured: there is no state to act from."""
        if self.frames is None:
            raise RuntimeError("call reset() before the first step() or action")

    # ------------------------------------------------------------------ step
    def apply_action(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Check and clamp, run one DLS IK step, and write joint targets; returns the applied action and the
        number of NaN entries per env."""
        self.require_reset()
        idx, ik, v, acfg = self.index, self.ik, self.view, self.cfg.actions
        actions, nan_count = checked_actions(actions, self.num_envs, self.num_actions)
        jacobian = chain_jacobian(
            self.frames.hand_pos, v.xanchor[:, ik.joint], v.xaxis[:, ik.joint], ik.is_hinge
        )
        error = wrist_pose_error(actions, acfg.pos_scale, acfg.rot_scale)
        q = v.qpos[:, ik.qpos]
        targets = np.clip(q + dls_step(jacobian, error, acfg.ik_damping), ik.limits[:, 0], ik.limits[:, 1])
        low, high = idx.hand_limits[:, 0], idx.hand_limits[:, 1]
        hand = low + 0.5 * (actions[:, 6:] + 1.0) * (high - low)
        v.ctrl[:, ik.act] = targets
        v.ctrl[:, idx.hand_act] = hand
        v.ctrl[:, idx.mimic_act] = hand[:, idx.mimic_leader]
        return actions, nan_count

    def step(self, actions: np.ndarray) -> StepResult:
        actions, nan_count = self.apply_action(actions)
        previous_vel = self._simulate_locked_base() if self.cfg.fixed_base else self._simulate()
        self.episode_length_buf += 1
        self.env_times += 1
        self.last_action = actions
        frames = self.frames = self.frame_reader.read(previous_vel=previous_vel, dt=self.cfg.physics.timestep)
        scfg = self.cfg.success
        dist = self.task_distances = TaskDistances.measure(frames, self.goal_pos)
        # Truncation reads the success counter before this step's success is added, as in the reference.
        truncated = time_out_or_held_success(
            self.episode_length_buf, self.max_episode_length, self.success_count, scfg.hold_steps
        )
        terminated = hand_too_far_or_too_fast(frames, dist, scfg) & ~truncated
        grasped = grasp_flag(dist, scfg)
        success = dist.goal < scfg.threshold
        self.success_count += success
        self.success_flag |= success
        ctx = RewardContext(
            self.goal_pos,
            self.goal_scale,
            self.default_hand_action,
            self.palm_rot_target if self.use_palm_rotation else None,
        )
        terms = reward_terms(frames, actions, ctx, dist, grasped, scfg)
        reward, weighted = total_reward(terms, self.cfg.rewards, self.cfg.reward_clip)
        means = np.mean(list(weighted.values()), axis=1)  # one reduction for all terms
        log: dict[str, float | np.ndarray] = {
            f"/reward/{k}": float(m) for k, m in zip(weighted, means, strict=True)
        }
        log["/task/grasp"] = float(grasped.mean())
        log["/task/success"] = float(success.mean())
        # Episode statistics over episodes that ended by truncation, as the reference's training log.
        ended = np.flatnonzero(truncated)
        if ended.size:
            log["/episode/success_flag"] = self.success_flag[ended].astype(np.float32)
            log["/episode/success"] = success[ended].astype(np.float32)
            log["/episode/success_ratio"] = ((self.goal_scale - dist.goal) / self.goal_scale)[ended]
        success_flag = self.success_flag.copy()
        done = np.flatnonzero(truncated | terminated)
        final_obs = self._observe(done) if done.size else np.empty((0, self.num_obs), np.float32)
        if done.size:
            self._reset_envs(done)
        self.obs = self._observe()
        return StepResult(
            self.obs, reward, terminated, truncated, success_flag, final_obs, done, weighted, log, nan_count
        )

    def _simulate(self) -> np.ndarray:
        """The physics substeps, positions and velocities current after them; returns the joint velocities
        before the last substep, which runs on its own: the acceleration is the velocity change over it."""
        if self.cfg.physics.substeps > 1:
            self.batch.step(nstep=self.cfg.physics.substeps - 1)
        previous_vel = self.frame_reader.joint_vel()
        self.batch.step(nstep=1, stage=mujoco.mjtStage.mjSTAGE_VEL)
        return previous_vel

    def _simulate_locked_base(self) -> np.ndarray:
        """As `_simulate`, with the base put back at its reset values and zero velocity after every substep:
        its servo alone would yield a little to the arm's reaction forces."""
        for _ in range(self.cfg.physics.substeps - 1):
            self._locked_substep()
        previous_vel = self.frame_reader.joint_vel()  # read once, before the last substep
        self._locked_substep()
        self.batch.forward(stage=mujoco.mjtStage.mjSTAGE_VEL)
        return previous_vel

    def _locked_substep(self) -> None:
        self.batch.step(nstep=1)
        self.view.qpos[:, self.base_qpos] = self.base_value
        self.view.qvel[:, self.base_dof] = 0.0

    def _observe(self, ids: np.ndarray | None = None) -> np.ndarray:
        if ids is None:
            frames, distances, ids = self.frames, self.task_distances, slice(None)
        else:
            frames, distances = self.frames.rows(ids), self.task_distances.rows(ids)
        return compute_observation(
            frames,
            distances,
            self.env_times[ids],
            self.last_action[ids],
            self.goal_pos[ids],
            self.joint_limits,
            self.cfg.obs_clip,
        )

    # ------------------------------------------------------------------ queries
    def distances(self) -> TaskDistances:
        return self.task_distances

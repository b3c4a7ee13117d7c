"""World-frame poses and velocities of the points the task talks about, read from a batch in one pass."""

from __future__ import annotations

from dataclasses import dataclass, fields

import mujoco
import numpy as np

from mobilemani_rl.envs.scene import SceneIndex
from mobilemani_rl.rotations import cross


class SimView:
    """Live (nsim, ...) numpy views of the batch fields the environment reads and writes."""

    def __init__(self, batch: mujoco.batch.Batch, model: mujoco.MjModel) -> None:
        self.qpos = batch.bind("qpos")
        self.qvel = batch.bind("qvel")
        self.ctrl = batch.bind("ctrl")
        self.mocap_pos = batch.bind("mocap_pos")
        self.mocap_quat = batch.bind("mocap_quat")
        self.qacc = batch.bind("qacc")
        self.xpos = batch.bind("xpos")
        self.xquat = batch.bind("xquat")
        self.site_xpos = batch.bind("site_xpos")
        self.cvel = batch.bind("cvel")
        self.xanchor = batch.bind("xanchor")
        self.xaxis = batch.bind("xaxis")
        self.subtree_com = batch.bind("subtree_com")
        self.body_rootid = model.body_rootid
        self.site_bodyid = model.site_bodyid


class EnvRows:
    """Row selection and row replacement for dataclasses whose fields are per-env arrays (leading axis)."""

    def rows(self, rows: np.ndarray):
        return type(self)(**{f.name: getattr(self, f.name)[rows] for f in fields(self)})

    def assign(self, rows: np.ndarray, other) -> None:
        """Overwrite the given env rows with `other`, which holds exactly those rows."""
        for f in fields(self):
            getattr(self, f.name)[rows] = getattr(other, f.name)


@dataclass
class Frames(EnvRows):
    """Everything observations, rewards and dones need, for a set of envs (leading axis)."""

    palm_pos: np.ndarray  # (n, 3)
    palm_quat: np.ndarray  # (n, 4) the hand body's orientation (palm sites carry no rotation of their own)
    palm_linvel: np.ndarray
    palm_angvel: np.ndarray
    finger_pos: np.ndarray  # (n, F, 3)
    finger_quat: np.ndarray  # (n, F, 4)
    finger_linvel: np.ndarray
    finger_angvel: np.ndarray
    body_pos: np.ndarray  # (n, B, 3) active bodies' origins
    hand_pos: np.ndarray  # (n, 3) IK body
    hand_quat: np.ndarray
    base_pos: np.ndarray
    base_quat: np.ndarray
    grasp_pos: np.ndarray  # (n, 3)
    grasp_quat: np.ndarray  # (n, 4) operated link's orientation
    grasp_linvel: np.ndarray
    joint_pos: np.ndarray  # (n, J) active joints: IK chain then hand
    joint_vel: np.ndarray
    joint_acc: np.ndarray


def _point_velocity(view: SimView, ids: np.ndarray, body: np.ndarray, point: np.ndarray,
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Linear velocity of world points fixed to `body`, and the bodies' angular velocity.

    cvel holds [angular; linear] velocity about the subtree centre of mass of each body's root.
    """
    rows = ids[:, None] if body.ndim == 1 else ids
    cvel = view.cvel[rows, body]
    anchor = view.subtree_com[rows, view.body_rootid[body]]
    angular = cvel[..., :3]
    return cvel[..., 3:] + cross(angular, point - anchor), angular


def read_frames(view: SimView, index: SceneIndex, ids: np.ndarray) -> Frames:
    site_body = view.site_bodyid
    palm_body = np.array([site_body[index.palm_site]])
    finger_body = site_body[index.finger_sites]
    palm_pos = view.site_xpos[ids, index.palm_site]
    finger_pos = view.site_xpos[ids[:, None], index.finger_sites]
    grasp_pos = view.site_xpos[ids, index.grasp_site]
    palm_lin, palm_ang = _point_velocity(view, ids, palm_body, palm_pos[:, None])
    finger_lin, finger_ang = _point_velocity(view, ids, finger_body, finger_pos)
    grasp_lin, _ = _point_velocity(view, ids, np.array([index.grasp_body]), grasp_pos[:, None])
    active_qpos = np.concatenate((index.ik_qpos, index.hand_qpos))
    active_dof = np.concatenate((index.ik_dof, index.hand_dof))
    return Frames(
        palm_pos=palm_pos,
        palm_quat=view.xquat[ids, index.hand_body],
        palm_linvel=palm_lin[:, 0],
        palm_angvel=palm_ang[:, 0],
        finger_pos=finger_pos,
        finger_quat=view.xquat[ids[:, None], finger_body],
        finger_linvel=finger_lin,
        finger_angvel=finger_ang,
        body_pos=view.xpos[ids[:, None], index.active_bodies],
        hand_pos=view.xpos[ids, index.hand_body],
        hand_quat=view.xquat[ids, index.hand_body],
        base_pos=view.xpos[ids, index.base_body],
        base_quat=view.xquat[ids, index.base_body],
        grasp_pos=grasp_pos,
        grasp_quat=view.xquat[ids, index.grasp_body],
        grasp_linvel=grasp_lin[:, 0],
        joint_pos=view.qpos[ids[:, None], active_qpos],
        joint_vel=view.qvel[ids[:, None], active_dof],
        joint_acc=view.qacc[ids[:, None], active_dof],
    )

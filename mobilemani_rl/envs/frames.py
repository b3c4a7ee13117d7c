"""World-frame poses and velocities of the points the task talks about, read from a batch in one pass."""

from __future__ import annotations

from dataclasses import dataclass, fields

import mujoco
import numpy as np

from mobilemani_rl.envs.scene import SceneIndex
from mobilemani_rl.utils.rotations import cross


class SimView:
    """Live (nsim, ...) numpy views of the batch fields the environment reads and writes."""

    # Each becomes an attribute of the same name: a live view, so writes reach the batch.
    FIELDS = tuple(
        "qpos qvel ctrl mocap_pos mocap_quat xpos xquat site_xpos cvel xanchor xaxis subtree_com".split()
    )

    def __init__(self, batch: mujoco.batch.Batch, model: mujoco.MjModel) -> None:
        for name in self.FIELDS:
            setattr(self, name, batch.bind(name))
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
    joint_acc: np.ndarray  # finite difference of joint_vel over the last physics substep (zero after a reset)


def _gather(field: np.ndarray, ids: np.ndarray | None, cols: np.ndarray | int) -> np.ndarray:
    """A copy of field[ids, cols] (all envs when ids is None: the per-step path, where np.take is
    cheapest)."""
    return np.take(field if ids is None else field[ids], cols, axis=1)


class FrameReader:
    """Reads `Frames` from a batch. The index arrays of every gather are derived once here, not per step."""

    def __init__(self, view: SimView, index: SceneIndex) -> None:
        self.view = view
        # Palm, fingers and grasp point are read in one gather and split: fewer small numpy calls per step.
        self.sites = np.concatenate(([index.palm_site], index.finger_sites, [index.grasp_site]))
        self.site_bodies = view.site_bodyid[self.sites]
        self.site_bodies[-1] = index.grasp_body
        self.site_roots = view.body_rootid[self.site_bodies]
        # Hand and base positions; hand, base and grasp-link orientations, then the fingers'.
        self.link_pos_bodies = np.array([index.hand_body, index.base_body])
        self.link_quat_bodies = np.concatenate(
            ([index.hand_body, index.base_body, index.grasp_body], self.site_bodies[1:-1])
        )
        self.active_bodies = index.active_bodies
        self.active_qpos = np.concatenate((index.ik_qpos, index.hand_qpos))
        self.active_dof = np.concatenate((index.ik_dof, index.hand_dof))

    def joint_vel(self) -> np.ndarray:
        """A copy of every env's active-joint velocities (the finite difference's earlier sample)."""
        return _gather(self.view.qvel, None, self.active_dof)

    def read(
        self, ids: np.ndarray | None = None, previous_vel: np.ndarray | None = None, dt: float = 1.0
    ) -> Frames:
        """Frames of the given envs, or of all envs when ids is None. The joint acceleration is the finite
        difference (joint_vel - previous_vel) / dt, as Isaac Lab computes it every physics step (MuJoCo's
        qacc is the acceleration before the last substep's constraint and implicit-damping updates, not the
        velocity change); zero when previous_vel is None (a reset)."""
        view = self.view
        points = _gather(view.site_xpos, ids, self.sites)
        # cvel holds [angular; linear] velocity about the subtree centre of mass of each body's root.
        cvel = _gather(view.cvel, ids, self.site_bodies)
        angvel = cvel[..., :3]
        linvel = cvel[..., 3:] + cross(angvel, points - _gather(view.subtree_com, ids, self.site_roots))
        link_pos = _gather(view.xpos, ids, self.link_pos_bodies)
        link_quat = _gather(view.xquat, ids, self.link_quat_bodies)
        joint_vel = _gather(view.qvel, ids, self.active_dof)
        return Frames(
            palm_pos=points[:, 0],
            palm_quat=link_quat[:, 0],
            palm_linvel=linvel[:, 0],
            palm_angvel=angvel[:, 0],
            finger_pos=points[:, 1:-1],
            finger_quat=link_quat[:, 3:],
            finger_linvel=linvel[:, 1:-1],
            finger_angvel=angvel[:, 1:-1],
            body_pos=_gather(view.xpos, ids, self.active_bodies),
            hand_pos=link_pos[:, 0],
            hand_quat=link_quat[:, 0],
            base_pos=link_pos[:, 1],
            base_quat=link_quat[:, 1],
            grasp_pos=points[:, -1],
            grasp_quat=link_quat[:, 2],
            grasp_linvel=linvel[:, -1],
            joint_pos=_gather(view.qpos, ids, self.active_qpos),
            joint_vel=joint_vel,
            joint_acc=np.zeros_like(joint_vel) if previous_vel is None else (joint_vel - previous_vel) / dt,
        )

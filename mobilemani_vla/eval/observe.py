"""Observations for evaluation policies, built from a live env batch in the dataset's feature names.

Only the keys a policy asks for are built; images are rendered only for envs whose first episode still runs.
Vectors and images come from mobilemani_data.frame, the frame builder the exporter uses too.
"""

from __future__ import annotations

import numpy as np

from mobilemani_data import schema
from mobilemani_data.frame import FrameState, frame_images, frame_vectors, robot_cameras
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.render import CameraRenderCfg, CameraRenderer
from mobilemani_vla.eval.policies.base import ACTIVE, PRIVILEGED_STATE, TASK, Observation

IMAGE_KEYS = {schema.image_key(c, m): (c, m) for c in schema.CAMERAS for m in schema.MODALITIES}
VECTOR_KEYS = (
    schema.STATE,
    schema.WORLD_STATE,
    schema.GRASP_POINT_BASE,
    schema.GOAL_POINT_BASE,
    PRIVILEGED_STATE,
)
KNOWN_KEYS = frozenset(IMAGE_KEYS) | frozenset(VECTOR_KEYS) | {TASK}


class ObservationBuilder:
    def __init__(
        self, env: MobileManiEnv, inputs: frozenset[str], instruction: str, width: int, height: int
    ) -> None:
        unknown = sorted(inputs - KNOWN_KEYS)
        if unknown:
            raise KeyError(
                f"the policy asks for unknown inputs {unknown}; the evaluator provides {sorted(KNOWN_KEYS)}"
            )
        self.env, self.inputs, self.instruction = env, inputs, instruction
        self.images = sorted(inputs & IMAGE_KEYS.keys())
        mj_cameras = robot_cameras(env.robot)
        self.cameras = {
            camera: mj_cameras[camera] for camera in sorted({IMAGE_KEYS[k][0] for k in self.images})
        }
        segmentation = any(IMAGE_KEYS[k][1] == "seg" for k in self.images)
        self.renderer = (
            CameraRenderer(
                env.model,
                CameraRenderCfg(width, height, tuple(self.cameras.values()), segmentation=segmentation),
            )
            if self.cameras
            else None
        )
        self.width, self.height = width, height
        self.grasp0 = np.zeros((env.num_envs, 3))

    def __call__(self, active: np.ndarray) -> Observation:
        env, f = self.env, self.env.frames
        started = env.env_times == 0  # the grasp point is taken at reset, like the exporter's first frame
        self.grasp0[started] = f.grasp_pos[started]
        state = FrameState(
            f.hand_pos,
            f.hand_quat,
            f.base_pos,
            f.base_quat,
            f.joint_pos[:, -len(env.robot.hand_joints) :],
            self.grasp0,
            env.goal_pos,
        )
        obs: Observation = {k: v for k, v in frame_vectors(state).items() if k in self.inputs}
        if PRIVILEGED_STATE in self.inputs:
            obs[PRIVILEGED_STATE] = np.asarray(env.obs, np.float32)
        obs[TASK] = [self.instruction] * env.num_envs
        obs[ACTIVE] = active
        obs.update(self._render(np.flatnonzero(active)))
        return obs

    def _render(self, rows: np.ndarray) -> dict[str, np.ndarray]:
        if self.renderer is None:
            return {}
        out = {k: np.zeros((self.env.num_envs, self.height, self.width, 3), np.uint8) for k in self.images}
        for i in rows:
            rendered = self.renderer.render(self.env.batch.get_data(int(i)))
            for key, image in frame_images(rendered, self.cameras, self.images).items():
                out[key][i] = image
        return out

    def close(self) -> None:
        if self.renderer is not None:
            self.renderer.close()

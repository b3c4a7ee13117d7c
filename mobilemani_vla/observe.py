"""Observations for evaluation policies, built from a live env batch in the dataset's feature names.

Only the keys a policy asks for are built; images are rendered only for envs whose first episode still runs.
Vectors follow mobilemani_data.convert (the exporter): world state = hand pos, hand RPY, base pos, base RPY, hand
joints; base-frame wrist pose; the episode's reset-time grasp point and its goal, expressed in the current base
frame. Images are RGB, depth (ray distance clipped to 0–5 m as 0–255) and segmentation (label x 100), 3 channels.
"""

from __future__ import annotations

import numpy as np

from mobilemani_data import schema
from mobilemani_rl.base_frame import points_to_base, pose_to_base
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.render import CameraRenderCfg, CameraRenderer
from mobilemani_vla.policies.base import ACTIVE, PRIVILEGED_STATE, TASK, Observation

IMAGE_KEYS = {schema.image_key(c, m): (c, m) for c in schema.CAMERAS for m in schema.MODALITIES}
VECTOR_KEYS = (schema.STATE, schema.WRIST_POSE_BASE, schema.GRASP_POINT_BASE, schema.GOAL_POINT_BASE,
               PRIVILEGED_STATE)
KNOWN_KEYS = frozenset(IMAGE_KEYS) | frozenset(VECTOR_KEYS) | {TASK}


class ObservationBuilder:
    def __init__(self, env: MobileManiEnv, inputs: frozenset[str], instruction: str, width: int,
                 height: int) -> None:
        unknown = sorted(inputs - KNOWN_KEYS)
        if unknown:
            raise KeyError(f"the policy asks for unknown inputs {unknown}; the evaluator provides {sorted(KNOWN_KEYS)}")
        self.env, self.inputs, self.instruction = env, inputs, instruction
        self.images = sorted(inputs & IMAGE_KEYS.keys())
        mj_cameras = {"head": env.robot.head_camera, "wrist": env.robot.wrist_camera}
        self.cameras = {camera: mj_cameras[camera] for camera in sorted({IMAGE_KEYS[k][0] for k in self.images})}
        self.renderer = CameraRenderer(env.model, CameraRenderCfg(width, height, tuple(self.cameras.values()))) \
            if self.cameras else None
        self.width, self.height = width, height
        self.grasp0 = np.zeros((env.num_envs, 3))

    def __call__(self, active: np.ndarray) -> Observation:
        env, f = self.env, self.env.frames
        started = env.env_times == 0  # the grasp point is taken at reset, like the exporter's first frame
        self.grasp0[started] = f.grasp_pos[started]
        vectors = {
            schema.STATE: lambda: schema.world_state(f.hand_pos, f.hand_quat, f.base_pos, f.base_quat,
                                                     f.joint_pos[:, -len(env.robot.hand_joints):]),
            schema.WRIST_POSE_BASE: lambda: pose_to_base(f.hand_pos, f.hand_quat, f.base_pos, f.base_quat),
            schema.GRASP_POINT_BASE: lambda: points_to_base(self.grasp0, f.base_pos, f.base_quat),
            schema.GOAL_POINT_BASE: lambda: points_to_base(env.goal_pos, f.base_pos, f.base_quat),
            PRIVILEGED_STATE: lambda: env.obs,
        }
        obs: Observation = {k: np.asarray(make(), np.float32) for k, make in vectors.items() if k in self.inputs}
        obs[TASK] = [self.instruction] * env.num_envs
        obs[ACTIVE] = active
        obs.update(self._render(np.flatnonzero(active)))
        return obs

    def _render(self, rows: np.ndarray) -> dict[str, np.ndarray]:
        if self.renderer is None:
            return {}
        out = {k: np.zeros((self.env.num_envs, self.height, self.width, 3), np.uint8) for k in self.images}
        for i in rows:
            frames = self.renderer.render(self.env.batch.get_data(int(i)))
            for key in self.images:
                camera, modality = IMAGE_KEYS[key]
                frame = frames[self.cameras[camera]]
                if modality == "rgb":
                    out[key][i] = frame.rgb
                elif modality == "depth":
                    out[key][i] = frame.depth_image[..., None]
                else:
                    out[key][i] = (frame.segmentation * schema.SEGMENTATION_SCALE)[..., None]
        return out

    def close(self) -> None:
        if self.renderer is not None:
            self.renderer.close()

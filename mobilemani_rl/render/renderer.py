"""Offscreen head/wrist camera renderer over any MjModel + MjData (e.g. `env.batch.get_data(i)`).

The data must have been through `mj_forward` (or a step): camera poses come from its `cam_xpos`/`cam_xmat`.

Per camera: one `mjv_updateScene`, one shaded pass whose colour and depth buffers are both read back, and one
segmentation pass (flat id colours, no lighting). Depth is returned as ray distance (see `depth.py`).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mobilemani_rl.render.config import CameraRenderCfg
from mobilemani_rl.render.depth import depth_to_uint8, ray_factor, z_depth_from_buffer
from mobilemani_rl.render.segmentation import geom_labels, segment_labels


@dataclass
class CameraFrame:
    rgb: np.ndarray  # (H, W, 3) uint8
    depth: np.ndarray  # (H, W) float32, ray distance in metres
    depth_image: np.ndarray  # (H, W) uint8, depth clipped to [0, depth_clip] and scaled to 0–255
    segmentation: np.ndarray | None  # (H, W) uint8: 0 background, 1 object, 2 robot; None if not rendered


def prepare_model(model: mujoco.MjModel, cfg: CameraRenderCfg) -> None:
    """Visual settings the context is created from: buffer size, MSAA, clip planes in metres, curve facets.

    They live on the model, so they also apply to any other renderer made from it afterwards.
    """
    model.vis.global_.offwidth = max(model.vis.global_.offwidth, cfg.width)
    model.vis.global_.offheight = max(model.vis.global_.offheight, cfg.height)
    model.vis.quality.offsamples = cfg.msaa_samples if cfg.multisampling else 0
    model.vis.map.znear = cfg.near / model.stat.extent
    model.vis.map.zfar = cfg.far / model.stat.extent
    model.vis.quality.numslices = cfg.curve_slices
    model.vis.quality.numstacks = max(2, cfg.curve_slices // 2)


class CameraRenderer:
    """Renders the configured cameras; one GL context per instance (not thread-safe)."""

    def __init__(self, model: mujoco.MjModel, cfg: CameraRenderCfg | None = None) -> None:
        self.cfg = cfg = cfg or CameraRenderCfg()
        prepare_model(model, cfg)
        self.model = model
        self._gl = mujoco.GLContext(cfg.width, cfg.height)
        self._gl.make_current()
        self._context = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_100)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._context)
        self._context.readDepthMap = mujoco.mjtDepthMap.mjDEPTH_ZEROFAR
        self._scene = mujoco.MjvScene(model, maxgeom=max(1000, 2 * model.ngeom))
        self._option = mujoco.MjvOption()
        self._camera = mujoco.MjvCamera()
        self._camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
        self._rect = mujoco.MjrRect(0, 0, cfg.width, cfg.height)
        self._labels = geom_labels(model)
        self._camera_ids = {name: model.camera(name).id for name in cfg.cameras}
        self._ray = {
            name: ray_factor(cfg.width, cfg.height, float(model.cam_fovy[cam]))
            for name, cam in self._camera_ids.items()
        }
        self._near, self._far = cfg.near, cfg.far
        shape = (cfg.height, cfg.width)
        self._rgb = np.empty((*shape, 3), np.uint8)
        self._ids = np.empty((*shape, 3), np.uint8)
        self._depth = np.empty(shape, np.float32)

    def render(self, data: mujoco.MjData) -> dict[str, CameraFrame]:
        return {name: self.render_camera(data, name) for name in self._camera_ids}

    def render_camera(self, data: mujoco.MjData, camera: str) -> CameraFrame:
        self._gl.make_current()
        self._camera.fixedcamid = self._camera_ids[camera]
        scene, flags = self._scene, self._scene.flags
        mujoco.mjv_updateScene(
            self.model, data, self._option, None, self._camera, mujoco.mjtCatBit.mjCAT_ALL, scene
        )
        flags[mujoco.mjtRndFlag.mjRND_SHADOW] = self.cfg.shadows
        flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = False
        mujoco.mjr_render(self._rect, scene, self._context)
        mujoco.mjr_readPixels(self._rgb, self._depth, self._rect, self._context)
        # GL rows run bottom-up.
        rgb = np.flipud(self._rgb).copy()
        distance = np.flipud(z_depth_from_buffer(self._depth, self._near, self._far)) * self._ray[camera]
        segmentation = self._segment(scene) if self.cfg.segmentation else None
        return CameraFrame(rgb, distance, depth_to_uint8(distance, self.cfg.depth_clip), segmentation)

    def _segment(self, scene: mujoco.MjvScene) -> np.ndarray:
        """The id-colour pass of the scene just rendered -> per-pixel labels."""
        flags = scene.flags
        flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = True
        mujoco.mjr_render(self._rect, scene, self._context)
        mujoco.mjr_readPixels(self._ids, None, self._rect, self._context)
        ids = np.flipud(self._ids).astype(np.int32)
        segid = ids[..., 0] | (ids[..., 1] << 8) | (ids[..., 2] << 16)
        return segment_labels(scene, self._labels)[np.minimum(segid, scene.ngeom)]

    def close(self) -> None:
        if self._gl is not None:
            self._gl.make_current()
            self._context.free()
            self._gl.free()
            self._gl = None

    def __enter__(self) -> CameraRenderer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

"""Renderer configuration (the reference's 520 x 520 head and wrist cameras)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class CameraRenderCfg:
    """Image size, cameras and the quality switches that dominate llvmpipe cost (shadows, multisampling)."""

    width: int = 520
    height: int = 520
    cameras: tuple[str, ...] = ("head_camera", "wrist_camera")
    segmentation: bool = True  # the second (id-colour) pass; off when no segmentation image is wanted
    shadows: bool = False
    multisampling: bool = False
    msaa_samples: int = 4  # used only with multisampling
    near: float = 0.01  # m; the wrist camera sees the fingers a few cm away
    far: float = 50.0  # m; beyond any room
    depth_clip: float = 5.0  # m mapped to 255 in the uint8 depth image, as in the reference
    # Facets around spheres, cylinders and capsules (MuJoCo's default is 28). On llvmpipe the cost of a frame
    # grows with the triangle count: 16 renders faster and still looks round at 520 px.
    curve_slices: int = 16

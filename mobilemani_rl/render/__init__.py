"""Head and wrist camera rendering: RGB, depth (ray distance) and object/robot segmentation."""

from mobilemani_rl.render.config import CameraRenderCfg
from mobilemani_rl.render.renderer import CameraFrame, CameraRenderer
from mobilemani_rl.render.segmentation import LABEL_BACKGROUND, LABEL_OBJECT, LABEL_ROBOT

__all__ = [
    "LABEL_BACKGROUND",
    "LABEL_OBJECT",
    "LABEL_ROBOT",
    "CameraFrame",
    "CameraRenderCfg",
    "CameraRenderer",
]

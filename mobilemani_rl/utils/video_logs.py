"""Quiet, explicit video libraries: one line instead of per-stream encoder banners and decoder tracebacks.

- SVT-AV1 prints a ~20-line banner for every stream it opens (6 per episode); errors only (SVT_LOG=1).
- FFmpeg (through PyAV) logs "moving the moov atom" for every file it finalises; errors only.
- lerobot logs a ~60-line traceback on every dataset open when torchcodec is installed but cannot load
  (it needs system FFmpeg libraries); this becomes one line saying that PyAV decodes instead, printed once.
"""

from __future__ import annotations

import logging
import os

import av

TORCHCODEC_NOTE = "torchcodec cannot load (it needs system FFmpeg libraries); videos are decoded with PyAV"


class _TorchcodecFallback(logging.Filter):
    """Replaces lerobot's torchcodec fallback warning with TORCHCODEC_NOTE the first time,
    drops it afterwards."""

    def __init__(self) -> None:
        super().__init__()
        self.said = False

    def filter(self, record: logging.LogRecord) -> bool:
        if "torchcodec" not in record.getMessage():
            return True
        if self.said:
            return False
        self.said = True
        record.msg, record.args = TORCHCODEC_NOTE, ()
        return True


def quiet_video_libraries() -> None:
    os.environ.setdefault("SVT_LOG", "1")
    av.logging.set_level(av.logging.ERROR)
    # lerobot's encoders hand logging back to FFmpeg's own callback
    av.logging.set_libav_level(av.logging.ERROR)
    logger = logging.getLogger("lerobot.utils.import_utils")
    if not any(isinstance(f, _TorchcodecFallback) for f in logger.filters):
        logger.addFilter(_TorchcodecFallback())

"""The decoded-frame cache lives on disk and is read through a read-only memory map, so a cache larger than
the machine's memory serves training: pages are read as samples ask for them and never copied whole."""

from pathlib import Path

import numpy as np
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata

from mobilemani_vla.data.frame_cache import IMAGES, cache_dir, cached_images
from mobilemani_vla.data.synthetic import write_synthetic_dataset

CAMERAS = ["head_rgb", "wrist_depth"]


def test_the_frame_cache_is_opened_memory_mapped_and_read_only(tmp_path):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=2, length=12)
    meta = LeRobotDatasetMetadata("synthetic/g1", root=root)
    path = cache_dir(root, CAMERAS, 32) / IMAGES
    for _ in ("built", "reused"):
        images = cached_images(root, meta, CAMERAS, 32, progress=False)
        assert isinstance(images, np.memmap) and images.mode == "r"
        assert Path(images.filename) == path.resolve() and not images.flags.writeable
        assert images.shape == (24, len(CAMERAS), 3, 32, 32) and images.dtype == np.uint8
    # A sample's frames are a small copy out of the map, as the training dataset reads them.
    frames = np.array(images[5])
    assert not isinstance(frames, np.memmap) and frames.shape == (len(CAMERAS), 3, 32, 32)
    assert frames.max() > frames.min()  # decoded pictures, not an unwritten file's zeros

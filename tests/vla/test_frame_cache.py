"""The decoded-frame cache lives on disk and is read through read-only memory maps, one per camera stream,
so a cache larger than the machine's memory serves training (pages are read as samples ask for them and never
copied whole) and runs reading different cameras of one dataset share the streams they have in common."""

import mmap

import numpy as np
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata

from mobilemani_vla.data.frame_cache import IMAGES, cache_dir, cached_images
from mobilemani_vla.data.synthetic import write_synthetic_dataset

CAMERAS = ["head_rgb", "wrist_depth"]


def test_the_frame_cache_is_opened_memory_mapped_and_read_only(tmp_path):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=2, length=12)
    meta = LeRobotDatasetMetadata("synthetic/g1", root=root)
    for _ in ("built", "reused"):
        streams = cached_images(root, meta, CAMERAS, 32, progress=False)
        assert list(streams) == CAMERAS
        for camera, images in streams.items():
            assert isinstance(images.base.base.obj, mmap.mmap)  # the file's pages, not a copy in memory
            assert not images.flags.writeable and not images.flags.owndata
            assert images.shape == (24, 3, 32, 32) and images.dtype == np.uint8
            assert np.array_equal(images, np.load(cache_dir(root, camera, 32) / IMAGES))
    # A sample's frames are a small copy out of the map, as the training dataset reads them.
    frames = np.array(streams["head_rgb"][5])
    assert frames.flags.owndata and frames.shape == (3, 32, 32)
    assert frames.max() > frames.min()  # decoded pictures, not an unwritten file's zeros


def test_camera_sets_share_the_streams_they_have_in_common(tmp_path):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=1, length=6)
    meta = LeRobotDatasetMetadata("synthetic/g1", root=root)
    first = cached_images(root, meta, CAMERAS, 32, progress=False)
    built = {c: (cache_dir(root, c, 32) / IMAGES).stat().st_mtime_ns for c in CAMERAS}
    second = cached_images(root, meta, ["wrist_depth", "wrist_rgb"], 32, progress=False)
    assert (cache_dir(root, "wrist_depth", 32) / IMAGES).stat().st_mtime_ns == built["wrist_depth"]  # reused
    assert np.array_equal(second["wrist_depth"], first["wrist_depth"])
    assert not np.array_equal(second["wrist_rgb"], second["wrist_depth"])  # its own stream, decoded
    assert sorted(p.name for p in (root / "vla_cache").iterdir() if p.is_dir()) == [
        "head_rgb_32px",
        "wrist_depth_32px",
        "wrist_rgb_32px",
    ]

"""lerobot-train's frame reader served from the frame cache returns what LeRobot's video decoder returns."""

from __future__ import annotations

from pathlib import Path

import torch
from lerobot.datasets.lerobot_dataset import LeRobotDataset

from mobilemani_data import schema
from mobilemani_vla.data.lerobot_frames import served_from_frame_cache
from mobilemani_vla.data.synthetic import write_synthetic_dataset


def open_dataset(root: Path) -> LeRobotDataset:
    # two past frames of one stream, and action chunks, as a stock policy with history would load them
    head = schema.image_key("head", "rgb")
    deltas = {head: [-2 / schema.FPS, 0.0], schema.ACTION: [i / schema.FPS for i in range(4)]}
    return LeRobotDataset("mobilemani/g1", root=root, delta_timestamps=deltas, video_backend="pyav")


def test_cached_frames_equal_the_decoded_ones(tmp_path):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=2, length=12, height=32, width=32)
    decoded = open_dataset(root)
    with served_from_frame_cache():
        cached = open_dataset(root)
        items = [cached[i] for i in (0, 1, 11, 12, 23)]  # episode starts (padded history), ends
    assert (root / "vla_cache").is_dir()
    for i, item in zip((0, 1, 11, 12, 23), items, strict=True):
        want = decoded[i]
        assert set(item) == set(want)
        for key, value in want.items():
            if isinstance(value, torch.Tensor):
                assert item[key].shape == value.shape and item[key].dtype == value.dtype, key
                torch.testing.assert_close(item[key], value, rtol=0, atol=1e-6, msg=key)
    assert open_dataset(root)[5][schema.image_key("head", "rgb")].shape == (2, 3, 32, 32)  # decoding again


def test_streams_the_cache_cannot_hold_are_decoded(tmp_path, capsys):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=1, length=6, height=48, width=64)
    decoded = open_dataset(root)[3]
    with served_from_frame_cache():
        served = open_dataset(root)[3]
    assert "frames decoded per sample" in capsys.readouterr().out and not (root / "vla_cache").exists()
    key = schema.image_key("head", "rgb")
    assert served[key].shape == (2, 3, 48, 64) and torch.equal(served[key], decoded[key])

"""lerobot-train's frame reader served from the frame cache returns what LeRobot's video decoder returns."""

from __future__ import annotations

from pathlib import Path

import pytest
import torch
from lerobot.datasets.lerobot_dataset import LeRobotDataset

from mobilemani_data import schema
from mobilemani_rl.registry import InputError
from mobilemani_vla.lerobot_frames import served_from_frame_cache
from mobilemani_vla.lerobot_train import check_arguments, frame_cache_flag
from mobilemani_vla.synthetic import write_synthetic_dataset


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


def test_frame_cache_flag_is_taken_out_of_lerobots_arguments():
    assert frame_cache_flag(["--policy.type=act"]) == (True, ["--policy.type=act"])
    assert frame_cache_flag(["--frame_cache=false", "--steps=3"]) == (False, ["--steps=3"])
    with pytest.raises(InputError, match="--frame_cache=yes: give --frame_cache=true"):
        frame_cache_flag(["--frame_cache=yes"])


def test_the_dataset_given_to_lerobot_train_is_checked_before_lerobot_opens_it(tmp_path):
    """LeRobot falls back to the hub for a missing local file and fails offline, naming none."""
    nowhere = tmp_path / "nowhere"
    for given in ([f"--dataset.root={nowhere}"], ["--dataset.root", str(nowhere)]):  # both of LeRobot's forms
        with pytest.raises(FileNotFoundError, match=f"dataset {nowhere} does not exist"):
            check_arguments(["--policy.type=act", "--dataset.streaming", *given])
    root = write_synthetic_dataset(tmp_path / "g1", episodes=1, length=5)
    check_arguments([f"--dataset.root={root}", "--dataset.repo_id=mobilemani/g1"])
    (root / "meta" / "info.json").unlink()
    with pytest.raises(FileNotFoundError, match="meta/info.json"):
        check_arguments([f"--dataset.root={root}"])
    check_arguments(["--resume=true", "--config_path=train_config.json"])  # its config names the dataset


@pytest.mark.parametrize("given", [["--steps=0"], ["--batch_size", "0"], ["--steps=abc"], ["--steps=-2"]])
def test_lerobot_trains_only_with_counts_of_at_least_one(given):
    """`make lerobot LEROBOT_STEPS=0` trained nothing, exited 0 and left evaluation to find no checkpoint."""
    key = given[0].split("=")[0]
    with pytest.raises(InputError, match=f"invalid values: {key}=.* \\(a whole number of at least 1\\)"):
        check_arguments(["--policy.type=act", *given])
    check_arguments(["--steps=3", "--batch_size=16"])

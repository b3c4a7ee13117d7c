"""A tiny dataset collected with the scripted teacher, exported to LeRobot, read back, replayed, validated."""

from pathlib import Path

import numpy as np
import pytest
from data_helpers import tiny_cfg
from lerobot.datasets.lerobot_dataset import LeRobotDataset

from mobilemani_data import schema
from mobilemani_data.collect import collect
from mobilemani_data.convert import FIRST_FRAME
from mobilemani_data.export import export
from mobilemani_data.metadata import read_episodes
from mobilemani_data.replay import Replayer
from mobilemani_data.shards import read_shard, shard_paths
from mobilemani_data.stats import action_roughness, dataset_stats, markdown
from mobilemani_data.validate import validate
from mobilemani_rl.envs.base_frame import action_to_base

CHUNK = 16


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    cfg = tiny_cfg(tmp_path_factory.mktemp("tiny"))
    collect(cfg)
    report = export(cfg)
    assert report.skipped == []
    return cfg


def test_every_combination_has_exactly_the_requested_successes(tiny):
    paths = shard_paths(Path(tiny.raw_dir), "g1")
    assert len(paths) == 8  # 2 objects x 2 skills x 2 scenes
    for path in paths:
        shard = read_shard(path)
        assert len(shard.episodes) == 2 and shard.header["collected"] == 2 and not shard.header["capped"]
        assert all(ep.arrays["success"].any() for ep in shard.episodes)


def test_lerobot_reads_back_16_step_action_chunks(tiny):
    deltas = {schema.ACTION: [i / schema.FPS for i in range(CHUNK)]}
    ds = LeRobotDataset(
        tiny.export.repo_id, root=tiny.dataset_dir, delta_timestamps=deltas, video_backend="pyav"
    )
    lines = read_episodes(Path(tiny.dataset_dir))
    assert ds.num_episodes == 16 and len(ds) == sum(line["length"] for line in lines)
    assert set(ds.meta.tasks.index) == {"open dishwasher", "close dishwasher", "pull cart", "push cart"}
    last = int(ds.meta.episodes["dataset_to_index"][0]) - 1
    item = ds[last - 3]
    assert item[schema.ACTION].shape == (CHUNK, 7)
    assert item[f"{schema.ACTION}_is_pad"].tolist() == [False] * 4 + [True] * (CHUNK - 4)
    assert item[schema.image_key("wrist", "seg")].shape == (3, 64, 64)
    seg = (item[schema.image_key("head", "seg")] * 255 / schema.SEGMENTATION_SCALE).round()
    assert set(seg.unique().tolist()) <= {0.0, 1.0, 2.0}


def test_frame_labels_are_the_action_taken_after_the_frame(tiny):
    line = read_episodes(Path(tiny.dataset_dir))[0]
    episode = read_shard(Path(tiny.raw_dir) / line["shard"]).episodes[line["shard_episode"]]
    ds = LeRobotDataset(tiny.export.repo_id, root=tiny.dataset_dir, video_backend="pyav")
    frame = ds[0]
    a = episode.arrays
    assert np.allclose(frame[schema.WORLD_ACTION].numpy(), a["action"][FIRST_FRAME], atol=1e-6)
    base = action_to_base(a["action"][FIRST_FRAME], a["base_quat"][FIRST_FRAME])
    assert np.allclose(frame[schema.ACTION].numpy(), base, atol=1e-5)
    assert np.allclose(frame[schema.WORLD_STATE].numpy()[:3], a["hand_pos"][FIRST_FRAME], atol=1e-6)
    assert line["length"] == episode.length - FIRST_FRAME
    for key in schema.EPISODE_METADATA:
        assert key in line
    assert (line["robot"], line["split"]) == ("g1", "train")


def test_replaying_a_recorded_episode_reproduces_its_states(tiny):
    shard = read_shard(shard_paths(Path(tiny.raw_dir), "g1")[0])
    errors = Replayer(shard).check(shard.episodes[1])
    assert errors.kinematics <= 1e-6 and errors.dynamics <= 1e-6


def test_validate_finds_nothing_wrong(tiny):
    assert validate(tiny) == []


def test_stats_report_mean_episode_length(tiny):
    table = dataset_stats(read_episodes(Path(tiny.dataset_dir)))
    total = table["total"]["all"]
    assert total["episodes"] == 16
    assert 90 <= total["mean_length"] <= 300  # the paper's episodes average 160 frames
    assert set(table["skill"]) == {"open", "close", "pull", "push"}
    assert set(table["category"]) == {"dishwasher", "cart"}
    print(markdown(table))


def test_action_roughness_counts_steps_within_episodes_only():
    actions = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [5.0, 5.0], [5.0, 5.0]])
    episode_index = np.array([0, 0, 0, 1, 1])
    # steps (1, 0), (0, 2) in episode 0 and (0, 0) in episode 1; the jump between episodes is not one
    assert action_roughness(actions, episode_index) == [round(1 / 3, 4), round(2 / 3, 4)]


def test_export_writes_only_the_chosen_streams_and_stock_policies_see_the_right_features(tiny, tmp_path):
    """export.cameras / export.modalities pick what a stock LeRobot policy trains on; LeRobot then types
    exactly `action` as the output and `observation.state` plus the chosen images as inputs.
    export.room_repaint repaints the room: the same states render with other colours, the same depth."""
    from dataclasses import replace

    from lerobot.configs.types import FeatureType
    from lerobot.utils.feature_utils import dataset_to_policy_features

    cfg = replace(
        tiny,
        dataset_dir=str(tmp_path / "lerobot"),
        export=replace(tiny.export, cameras=["head"], modalities=["rgb", "depth"], room_repaint=0.6),
    )
    export(cfg)
    assert validate(cfg) == []
    ds = LeRobotDataset(cfg.export.repo_id, root=cfg.dataset_dir, video_backend="pyav")
    rgb, depth = schema.image_key("head", "rgb"), schema.image_key("head", "depth")
    assert ds.meta.video_keys == [rgb, depth]
    policy = dataset_to_policy_features(ds.meta.features)
    assert [k for k, f in policy.items() if f.type is FeatureType.ACTION] == [schema.ACTION]
    assert [k for k, f in policy.items() if f.type is FeatureType.STATE] == [schema.STATE]
    assert policy[schema.STATE].shape == (schema.state_dim(1),)
    built = LeRobotDataset(tiny.export.repo_id, root=tiny.dataset_dir, video_backend="pyav")
    repainted_rgb = np.mean([(ds[i][rgb] - built[i][rgb]).abs().mean().item() for i in (0, 100)])
    assert repainted_rgb > 0.02  # images in [0, 1]: the room's colours changed
    assert max((ds[i][depth] - built[i][depth]).abs().mean().item() for i in (0, 100)) < 0.01
    with pytest.raises(ValueError, match=r"export.modalities \['rgb', 'ir'\].*'seg'"):
        replace(cfg, export=replace(cfg.export, modalities=["rgb", "ir"])).check()

"""Training inputs equal evaluation inputs: a collected, exported episode against the closed-loop observer;
the state encoding the VLA learns from (continuous rotations, global bounds that clip nothing).

The scripted teacher collects one episode through the real collection pipeline while the evaluator's
ObservationBuilder watches the same env at every step; the episode is then exported through the real exporter.
Every vector of every exported frame must equal the observer's at that step, and every image must match within
the video codec's error (H.264 at a high quality, crf 10: at 64 px its 4:2:0 chroma costs ~3 levels of 255).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from data_helpers import tiny_cfg
from lerobot.datasets.lerobot_dataset import LeRobotDataset

from mobilemani_data import collect as collect_module
from mobilemani_data import schema
from mobilemani_data.collect import collect
from mobilemani_data.export import export
from mobilemani_data.teachers import Teacher, build_teacher
from mobilemani_vla.config import STATES, InputsCfg, VLACfg
from mobilemani_vla.config import DataCfg as VLADataCfg
from mobilemani_vla.data.dataset import fit_normalizer, open_data
from mobilemani_vla.eval.observe import IMAGE_KEYS, ObservationBuilder
from mobilemani_vla.eval.policies.base import ACTIVE, TASK

VECTORS = (schema.STATE, schema.WORLD_STATE, schema.GRASP_POINT_BASE, schema.GOAL_POINT_BASE)
SIZE = 64


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """(exported dataset, episode metadata, the observer's observations per control step)."""
    cfg = tiny_cfg(
        tmp_path_factory.mktemp("parity"),
        "subset.objects=[test/box]",
        "subset.skills=[open]",
        "subset.scenes_per_object=1",
        "subset.episodes=1",
        "collect.num_envs=2",
        "export.crf=10",
        f"export.width={SIZE}",
        f"export.height={SIZE}",
    )
    observed: list[dict] = []

    def watched_teacher(*args, **kwargs) -> Teacher:
        teacher = build_teacher(*args, **kwargs)
        builder = ObservationBuilder(
            teacher.env, frozenset(IMAGE_KEYS) | frozenset(VECTORS) | {TASK}, "", SIZE, SIZE
        )

        def policy() -> np.ndarray:  # called in the state the recorder has just snapshotted
            obs = builder(np.ones(teacher.env.num_envs, dtype=bool))
            observed.append({k: np.array(v) for k, v in obs.items() if k not in (TASK, ACTIVE)})
            return teacher.policy()

        return Teacher(teacher.env, policy, teacher.name)

    mp = pytest.MonkeyPatch()
    mp.setattr(collect_module, "build_teacher", watched_teacher)
    try:
        collect(cfg)
    finally:
        mp.undo()
    export(cfg)
    root = Path(cfg.dataset_dir)
    episode = json.loads((root / schema.EPISODES_FILE).read_text().splitlines()[0])
    return LeRobotDataset(cfg.export.repo_id, root=root), episode, observed


def test_exported_vectors_equal_the_observers(recorded):
    dataset, episode, observed = recorded
    assert episode["round"] == 0  # the observer's step t is the episode's recorded state t
    slot = episode["env_slot"]
    for i in range(episode["length"]):
        frame = dataset[i]
        for key in VECTORS:
            np.testing.assert_array_equal(
                frame[key].numpy(), observed[i + 1][key][slot], err_msg=f"{key} frame {i}"
            )


def test_exported_images_match_the_observers_within_codec_error(recorded):
    dataset, episode, observed = recorded
    slot = episode["env_slot"]
    for i in (0, episode["length"] // 2, episode["length"] - 1):
        frame = dataset[i]
        for key in IMAGE_KEYS:
            decoded = frame[key].permute(1, 2, 0).numpy() * 255.0
            live = observed[i + 1][key][slot].astype(np.float64)
            assert live.std() > 0, f"{key} frame {i} is blank"
            error = np.abs(decoded - live)
            assert error.mean() < 4.0 and np.percentile(error, 99) < 40.0, (
                f"{key} frame {i}: {error.mean():.2f}"
            )


def test_state_encoding_is_continuous_and_unclipped(recorded):
    """The wrist rotation has no wrap (6D, unit columns, smooth along the episode) and the project's global
    normalisation bounds clip < 1% of the training values of every state and action dimension."""
    dataset, _, _ = recorded
    cfg = VLACfg(
        data=VLADataCfg(root=str(dataset.root), repo_id=dataset.repo_id, heldout_episodes=0),
        inputs=InputsCfg(cameras=["head_rgb"], states=list(STATES)),
    )
    data = open_data(cfg, 32, progress=False)
    rows = data.table.rows(data.train_episodes)
    normalizer = fit_normalizer(data.table, rows, cfg.inputs.states)
    for key in normalizer.bounds:
        assert normalizer.clipped_fraction(key, data.table.columns[key][rows]) < 0.01, key
    pose = data.table.columns[schema.STATE][rows][:, : schema.WRIST_POSE_DIM]
    np.testing.assert_allclose(np.linalg.norm(pose[:, 3:6], axis=1), 1.0, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(pose[:, 6:9], axis=1), 1.0, atol=1e-5)
    assert np.abs(np.diff(pose, axis=0)).max() < 0.1  # one control step moves the wrist a few mm / degrees

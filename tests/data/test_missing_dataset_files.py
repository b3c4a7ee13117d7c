"""A dataset with nothing in it or with a file missing is named, not read halfway."""

from pathlib import Path

import pytest
from data_helpers import tiny_cfg
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata

from mobilemani_data.metadata import check_dataset_files
from mobilemani_data.validate import validate
from mobilemani_vla.data.synthetic import write_synthetic_dataset


def test_validating_nothing_is_a_problem_not_valid(tmp_path):
    problems = validate(tiny_cfg(tmp_path / "nowhere"))
    assert len(problems) == 1 and "nothing to validate" in problems[0]


def test_a_deleted_dataset_file_is_named(tmp_path):
    root = write_synthetic_dataset(tmp_path / "g1", episodes=1, length=5)
    meta = LeRobotDatasetMetadata("synthetic/g1", root=root)
    check_dataset_files(meta)
    video = root / meta.get_video_file_path(0, meta.video_keys[0])
    video.unlink()
    with pytest.raises(FileNotFoundError, match=str(Path(video).name)):
        check_dataset_files(meta)


@pytest.mark.parametrize(
    ("deleted", "named"), [("meta/tasks.parquet", "meta/tasks.parquet"), ("meta/episodes", "meta/episodes")]
)
def test_a_deleted_metadata_file_is_named(tmp_path, deleted, named):
    import shutil

    from mobilemani_data.metadata import open_dataset_metadata

    root = write_synthetic_dataset(tmp_path / "g1", episodes=1, length=5)
    open_dataset_metadata("synthetic/g1", root)
    victim = root / deleted
    shutil.rmtree(victim) if victim.is_dir() else victim.unlink()
    with pytest.raises(FileNotFoundError, match=named):
        open_dataset_metadata("synthetic/g1", root)

"""Bad input stops with one message naming the key or file, before anything is written."""

from pathlib import Path

import pytest
from data_helpers import tiny_cfg
from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata

from mobilemani_data.metadata import check_dataset_files
from mobilemani_data.validate import validate
from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_vla.synthetic import write_synthetic_dataset


def test_non_positive_counts_name_their_keys(tmp_path):
    with pytest.raises(ValueError, match=r"subset.episodes=-2, collect.num_envs=0"):
        tiny_cfg(tmp_path, "subset.episodes=-2", "collect.num_envs=0")
    with pytest.raises(ValueError, match="num_envs=0"):
        MobileManiEnv(EnvCfg(num_envs=0))
    assert not any(tmp_path.iterdir())


def test_non_positive_evaluation_counts_name_their_keys():
    from hydra import compose, initialize_config_dir

    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.schema import to_dataclass
    from mobilemani_vla.eval_config import EvalCfg

    conf = str(Path(__file__).resolve().parents[1] / "conf")
    with initialize_config_dir(config_dir=conf, version_base="1.3"):
        cfg = compose(config_name="eval", overrides=["episodes_per_batch=0"])
    with pytest.raises(ValueError, match="episodes_per_batch=0"):
        to_dataclass(with_env_task(cfg), EvalCfg).check_counts()


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


def test_a_checkpoint_from_an_older_dataset_layout_is_refused_by_name():
    from mobilemani_vla.normalizer import Normalizer
    from mobilemani_vla.processor import VLAProcessor
    from mobilemani_vla.tokenizer import build_word_tokenizer

    old_bounds = Normalizer(
        {"action": ([-1.0] * 7, [1.0] * 7), "observation.wrist_pose_base": ([-1.0] * 9, [1.0] * 9)}
    )
    with pytest.raises(KeyError, match=r"no \['observation.state'\].*older dataset layout"):
        VLAProcessor(build_word_tokenizer(), old_bounds, ["head_rgb"], ["wrist_pose"], 32, "{instruction}")

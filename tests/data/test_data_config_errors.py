"""Dataset config values (collection, export, validation, preview, bench) are named by their keys before
anything is collected or written."""

import pytest
from data_helpers import tiny_cfg

from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv


def test_non_positive_counts_name_their_keys(tmp_path):
    with pytest.raises(ValueError, match=r"subset.episodes=-2, collect.num_envs=0, collect.workers=0"):
        tiny_cfg(tmp_path, "subset.episodes=-2", "collect.num_envs=0", "collect.workers=0")
    with pytest.raises(ValueError, match="num_envs=0"):
        MobileManiEnv(EnvCfg(num_envs=0))
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("export.gop=0", "export.gop=0"),
        ("export.episodes_per_combination=0", "export.episodes_per_combination=0"),
        (
            "export.workers=0 export.combinations_per_part=-1",
            "export.workers=0, export.combinations_per_part=-1",
        ),
        ("collect.action_noise=-0.3", r"collect.action_noise=-0.3 \(a standard deviation, >= 0\)"),
        ("collect.compression=12", r"collect.compression=12 \(a gzip level, 0 to 9\)"),
        ("teacher.min_train_success=10", r"teacher.min_train_success=10.0 \(a success rate, 0 to 1\)"),
        ("export.crf=-1", r"export.crf=-1 \(0 to 63"),
        ("export.action_convention=referense", "unknown export.action_convention 'referense'"),
        ("export.ppo_label_window=4", r"export.ppo_label_window=4 must be an odd whole number"),
        ("env.episode_length=0", "env.episode_length=0"),
        ("validate.replay_episodes=-1", r"validate.replay_episodes=-1 \(>= 0\)"),
        ("preview.episodes=0", "preview.episodes=0"),
        ("bench.sizes=[224,0]", r"bench.sizes=\[224, 0\] \(image sizes in pixels, >= 1\)"),
        # the encoder refused these when the export's first frame came, after collection
        (
            "export.vcodec=libsvtav1 export.preset=99",
            r"export.vcodec=libsvtav1 does not open with export.width=64, export.height=64, export.crf=30, "
            r"export.gop=2, export.preset=99: \[Errno 34\] Numerical result out of range",
        ),
        (
            "export.width=65",
            r"export.vcodec=h264 does not open with export.width=65, .*width not divisible by 2 \(65x64\) "
            r"\(4:2:0 video such as h264's needs even sizes\)$",
        ),
    ],
)
def test_data_values_name_their_keys_before_anything_is_written(tmp_path, override, named):
    with pytest.raises(ValueError, match=named):
        tiny_cfg(tmp_path, *override.split())
    assert not any(tmp_path.iterdir())


def test_export_values_are_checked_with_the_data_config_before_collection():
    """`make data` collects before it exports: a bad export value stopped it only after collecting."""
    from mobilemani_data.config import DataCfg, ExportCfg

    with pytest.raises(ValueError, match="export.vcodec='foo' is no video encoder"):
        ExportCfg(vcodec="foo").check()
    ExportCfg(vcodec="h264").check()
    with pytest.raises(ValueError, match=r"export.room_repaint=1.5 must lie in \[0, 1\]"):
        ExportCfg(vcodec="h264", room_repaint=1.5).check()
    with pytest.raises(
        ValueError, match=r"invalid export.modalities \['rgb', 'thermal'\]: name one or more of"
    ):
        DataCfg(export=ExportCfg(modalities=["rgb", "thermal"])).check()

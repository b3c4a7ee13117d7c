"""VLA training configs: each bad value named by its key, the episodes it names checked against the
dataset's."""

import pytest

from mobilemani_vla.data.synthetic import write_synthetic_dataset


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("diffusion.ddim_steps=0", "diffusion.ddim_steps=0"),
        ("diffusion.ddim_steps=500", r"diffusion.ddim_steps=500 \(<= its timesteps\)"),
        ("diffusion.cfg_dropout=1", r"diffusion.cfg_dropout=1.0 \(in \[0, 1\)"),
        ("inputs.state_dropout=1", r"inputs.state_dropout=1.0 \(in \[0, 1\)"),
        (
            "inputs.grasp_point_noise=0.02",
            r"inputs.grasp_point_noise=0.02 \(>= 0, and 0 unless inputs.states holds grasp_point\)",
        ),
        ("train.lr=-0.001", r"train.lr=-0.001 \(above 0\)"),
        ("train.ema_decay=1.5", r"train.ema_decay=1.5 \(in \[0, 1\); 0 keeps no average\)"),
        ("data.heldout_episodes=-1", r"data.heldout_episodes=-1 \(>= 0\)"),
        (
            "train.mixed_precision=bf32",
            r"invalid train.mixed_precision \['bf32'\]: each must be one of \['no'",
        ),
        ("train.lr_schedule=cosin", r"invalid train.lr_schedule \['cosin'\]: each must be one of \['linear'"),
        # each reached a library's traceback when the model or the dataset was built, or ran without a word
        (
            "diffusion.beta_schedule=cosine",
            r"invalid diffusion.beta_schedule \['cosine'\]: each must be one of \['linear', 'scaled_linear'",
        ),
        (
            "data.video_backend=ffmpeg",
            r"invalid data.video_backend \['ffmpeg'\]: each must be one of \['pyav'",
        ),
        ("diffusion.cfg_scale=-1", r"diffusion.cfg_scale=-1.0 \(>= 0; 1: no guidance\)"),
        ("train.diagnose_cfg_scales=[1,-2]", r"train.diagnose_cfg_scales=\[1.0, -2.0\] \(guidance scales"),
        (
            "model.vision.num_attention_heads=3",
            r"model.vision.num_attention_heads=3 \(a divisor of model.vision.hidden_size=32\)",
        ),
        (
            "model.text.num_key_value_heads=3",
            r"model.text.num_key_value_heads=3 \(a divisor of model.text.num_attention_heads=2\)",
        ),
    ],
)
def test_vla_training_values_name_their_keys(override, named):
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.config import compose_vla_cfg

    with pytest.raises(InputError, match=named):
        compose_vla_cfg([override])


@pytest.mark.parametrize(
    ("episodes", "named"),
    [
        # it said "data.heldout_episodes=4 leaves no training episode of 1", of an episode that does not exist
        (
            [999],
            r"data.episodes=\[999\]: name one or more of the 3 episodes of .* \(0 to 2\), .*"
            r"not among them: \[999\]",
        ),
        ([1, 1], r"data.episodes=\[1, 1\]: .* without repeats"),
        ([], r"data.episodes=\[\]: name one or more"),
    ],
)
def test_vla_training_episodes_must_be_the_datasets(tmp_path, episodes, named):
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.config import compose_vla_cfg
    from mobilemani_vla.data.dataset import open_data

    root = write_synthetic_dataset(tmp_path / "g1", episodes=3, length=5)
    cfg = compose_vla_cfg([f"data.root={root}", "data.repo_id=synthetic/g1", "data.heldout_episodes=0"])
    cfg.data.episodes = episodes
    with pytest.raises(InputError, match=named):
        open_data(cfg, 32, progress=False)


def test_vla_training_counts_and_logger_name_their_keys():
    from mobilemani_vla.config import VLACfg

    cfg = VLACfg()
    cfg.train.steps, cfg.train.batch_size = 0, -1
    with pytest.raises(ValueError, match=r"train.steps=0, train.batch_size=-1"):
        cfg.validate()
    cfg = VLACfg()
    cfg.train.logger = "tensorboard"
    with pytest.raises(ValueError, match=r"train.logger \['tensorboard'\]"):
        cfg.validate()

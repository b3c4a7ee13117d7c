"""Closed-loop evaluation configs and policy settings: each bad value named by its key, before anything
is written."""

import pytest
import torch
from checkout import ROOT
from roots import compose_root


def test_non_positive_evaluation_counts_name_their_keys():
    from hydra import compose, initialize_config_dir

    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_vla.eval.config import EvalCfg

    conf = str(ROOT / "conf")
    with initialize_config_dir(config_dir=conf, version_base="1.3"):
        cfg = compose(config_name="eval", overrides=["episodes_per_batch=0", "workers=0"])
    with pytest.raises(ValueError, match="episodes_per_batch=0, workers=0"):
        to_dataclass(with_env_task(cfg), EvalCfg).check()


@pytest.mark.parametrize("checkpoint", [None, ""])  # "": `policy.checkpoint=` on the command line
def test_a_model_policy_without_a_checkpoint_names_the_key(checkpoint):
    from mobilemani_vla.eval.config import PolicyCfg
    from mobilemani_vla.eval.policies.factory import build_policy

    for kind in ("vla", "lerobot"):
        with pytest.raises(ValueError, match=f"policy.kind={kind} needs policy.checkpoint="):
            build_policy(PolicyCfg(kind=kind, checkpoint=checkpoint))
    assert build_policy(PolicyCfg(kind="teacher", checkpoint=checkpoint)).checkpoint is None


def test_a_policy_setting_its_kind_does_not_read_is_refused():
    """`make eval POLICY=scripted CHECKPOINT=...` evaluated the scripted policy without a word."""
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.eval.config import PolicyCfg
    from mobilemani_vla.eval.policies.factory import build_policy

    for kind in ("scripted", "random"):
        with pytest.raises(
            InputError, match=f"policy.kind={kind} does not read policy.checkpoint=ckpt; leave it out"
        ):
            build_policy(PolicyCfg(kind=kind, checkpoint="ckpt"))
    rename = {"observation.images.head_rgb": "observation.images.top"}
    with pytest.raises(
        InputError, match=r"policy.kind=teacher does not read policy.device=cuda, policy.rename="
    ):
        build_policy(PolicyCfg(kind="teacher", rename=rename, device="cuda"))
    with pytest.raises(InputError, match="policy.kind=vla does not read policy.runs_dir=runs/teachers"):
        build_policy(PolicyCfg(kind="vla", checkpoint="ckpt", runs_dir="runs/teachers"))
    with pytest.raises(InputError, match="policy.kind=lerobot does not read policy.null_image=True"):
        build_policy(PolicyCfg(kind="lerobot", checkpoint="ckpt", null_image=True))


def test_a_fixed_action_index_outside_the_chunk_stops_before_anything_is_written(tmp_path):
    """It stopped at the first step, after the run's config.json was written."""
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.eval.config import EvalCfg
    from mobilemani_vla.eval.evaluate import evaluate

    cfg = compose_root(
        "eval",
        ["eval/policy=scripted", "eval/protocol=small", f"output_dir={tmp_path}", "ensemble.action_index=1"],
    )
    with pytest.raises(
        InputError, match="ensemble.action_index=1 is outside the policy's chunk of 1 actions"
    ):
        evaluate(to_dataclass(with_env_task(cfg), EvalCfg).check())
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("ensemble.horizon=0", "ensemble.horizon=0"),
        ("policy.batch_size=0", "policy.batch_size=0"),
        ("env.episode_length=0", "env.episode_length=0"),
        ("env.physics.substeps=0", "env.physics.substeps=0"),
        ("video_episodes=-1", r"video_episodes=-1 \(episodes to record, >= 0\)"),
        ("ensemble.action_index=-2", r"ensemble.action_index=-2 \(-1: adaptive ensemble"),
        (
            "action_convention=foo",
            "unknown action_convention 'foo'; valid action_conventions: conjugate, reference",
        ),
        ("image_size=[64]", r"image_size=\[64\] \(\[height, width\]\)"),
        ("image_size=[0,0]", r"image_size=\[0, 0\] \(\[height, width\]\)"),
        # reached torch's "Found no NVIDIA driver on your system" once the checkpoint loaded
        (f"policy.device=cuda:{torch.cuda.device_count()}", "CUDA device\\(s\\); use policy.device=cpu"),
    ],
)
def test_evaluation_config_names_each_bad_value(tmp_path, override, named):
    from mobilemani_rl.envs.config import with_env_task
    from mobilemani_rl.utils.config_store import to_dataclass
    from mobilemani_rl.utils.errors import InputError
    from mobilemani_vla.eval.config import EvalCfg

    cfg = compose_root("eval", ["eval/policy=scripted", f"output_dir={tmp_path / 'out'}", override])
    with pytest.raises(InputError, match=named):
        to_dataclass(with_env_task(cfg), EvalCfg).check()

"""LeRobot policies (ACT, Diffusion Policy, SmolVLA) built for our dataset, saved and loaded back with
LeRobot's API, run through the harness."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch
from checkout import ROOT, checkout_env

from mobilemani_data import schema
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_vla.data.dataset import dataset_digest
from mobilemani_vla.data.synthetic import write_synthetic_dataset
from mobilemani_vla.eval.harness import run_batch
from mobilemani_vla.eval.policies.lerobot import LeRobotEvalPolicy
from mobilemani_vla.model.ensemble import EnsembleCfg
from mobilemani_vla.smolvla_backbone import write_smolvlm_backbone

HEAD_RGB = schema.image_key("head", "rgb")


def save_tiny_policy(
    dataset_root: Path, out: Path, config_cls: type, policy_cls: type, **config: object
) -> Path:
    """What lerobot-train leaves in pretrained_model, built directly (and untrained) for the head camera and
    the state: config, weights, and the pre/post-processors with the dataset's statistics."""
    from lerobot.datasets.dataset_metadata import LeRobotDatasetMetadata
    from lerobot.policies.factory import make_pre_post_processors
    from lerobot.utils.feature_utils import dataset_to_policy_features

    meta = LeRobotDatasetMetadata("synthetic/g1", root=dataset_root)
    features = dataset_to_policy_features(meta.features)
    policy_config = config_cls(
        input_features={k: features[k] for k in (HEAD_RGB, schema.STATE)},
        output_features={schema.ACTION: features[schema.ACTION]},
        pretrained_backbone_weights=None,
        device="cpu",
        **config,
    )
    policy = policy_cls(policy_config)
    pre, post = make_pre_post_processors(policy_config, dataset_stats=meta.stats)
    for part in (policy, pre, post):
        part.save_pretrained(out)
    return out


def save_tiny_act(dataset_root: Path, out: Path) -> Path:
    """`lerobot-train --policy.type=act --policy.pretrained_backbone_weights=null`, at test size."""
    from lerobot.policies.act.configuration_act import ACTConfig
    from lerobot.policies.act.modeling_act import ACTPolicy

    return save_tiny_policy(
        dataset_root,
        out,
        ACTConfig,
        ACTPolicy,
        chunk_size=16,
        n_action_steps=16,
        dim_model=32,
        n_heads=2,
        dim_feedforward=64,
        n_encoder_layers=1,
        n_decoder_layers=1,
        latent_dim=8,
    )


def save_tiny_diffusion(dataset_root: Path, out: Path) -> Path:
    """What `make lerobot LEROBOT_POLICY=diffusion` trains, at test size: a policy that was fed observation
    windows (of one step) in training."""
    from lerobot.policies.diffusion.configuration_diffusion import DiffusionConfig
    from lerobot.policies.diffusion.modeling_diffusion import DiffusionPolicy

    return save_tiny_policy(
        dataset_root,
        out,
        DiffusionConfig,
        DiffusionPolicy,
        n_obs_steps=1,
        horizon=16,
        n_action_steps=8,
        crop_shape=None,
        down_dims=(16, 32),
        num_inference_steps=2,
    )


def test_lerobot_diffusion_policy_gets_one_step_observation_windows(tmp_path):
    data = write_synthetic_dataset(tmp_path / "data", episodes=1, length=20)
    policy = LeRobotEvalPolicy(save_tiny_diffusion(data, tmp_path / "pretrained_model"))
    assert policy.name == "lerobot_diffusion" and policy.windowed and policy.image_size == (48, 64)
    obs = {
        HEAD_RGB: np.zeros((2, 48, 64, 3), np.uint8),
        schema.STATE: np.zeros((2, schema.state_dim(1)), np.float32),
        "task": ["open box"] * 2,
        "active": np.array([True, True]),
    }
    policy.start(None, seed=5)
    chunks = policy.act(obs)
    assert chunks.shape == (2, 8, 7) and np.all(np.isfinite(chunks))
    # Its noise comes from torch's global generator, which start() seeds: one batch seed, the same chunks.
    assert not np.allclose(policy.act(obs), chunks)
    policy.start(None, seed=5)
    np.testing.assert_array_equal(policy.act(obs), chunks)


@pytest.fixture(scope="module")
def act_dir(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("lerobot")
    return save_tiny_act(
        write_synthetic_dataset(root / "data", episodes=1, length=20), root / "pretrained_model"
    )


def test_lerobot_act_policy_runs_through_the_harness(act_dir):
    policy = LeRobotEvalPolicy(act_dir, rename={})
    assert policy.name == "lerobot_act" and policy.action_frame == "base"
    assert policy.inputs == {HEAD_RGB, schema.STATE, "task"} and not policy.windowed
    assert policy.image_size == (48, 64) and policy.action_dim == 7
    env = MobileManiEnv(
        EnvCfg(num_envs=2, seed=0, episode_length=6, task=TaskCfg(object="test/box", skill="open"))
    )
    stats = run_batch(env, policy, 0, "open box", EnsembleCfg(), image_size=(48, 64))
    assert stats.length.max() <= 6 and stats.success.shape == (2,)
    obs = {
        HEAD_RGB: np.zeros((3, 48, 64, 3), np.uint8),
        schema.STATE: np.zeros((3, schema.state_dim(1)), np.float32),
        "task": ["open box"] * 3,
        "active": np.array([True, False, True]),
    }
    chunks = policy.act(obs)
    assert chunks.shape == (3, 16, 7) and np.all(chunks[1] == 0) and np.all(np.isfinite(chunks))


def test_lerobot_features_can_be_renamed(act_dir):
    policy = LeRobotEvalPolicy(act_dir, rename={schema.image_key("wrist", "rgb"): HEAD_RGB})
    assert schema.image_key("wrist", "rgb") in policy.inputs and HEAD_RGB not in policy.inputs


@pytest.fixture(scope="module")
def smolvla_dir(tmp_path_factory) -> Path:
    """`make lerobot LEROBOT_POLICY=smolvla` at test size: a local untrained SmolVLM backbone, then one
    `lerobot-train` step of SmolVLA on it (no download), leaving LeRobot's pretrained_model."""
    root = tmp_path_factory.mktemp("smolvla")
    data = write_synthetic_dataset(root / "data", episodes=1, length=20)
    backbone = write_smolvlm_backbone(
        root / "smolvlm", hidden_size=64, num_layers=2, vision_hidden_size=32, vision_layers=1, image_size=64
    )
    flags = [
        f"--policy.vlm_model_name={backbone}",
        "--policy.load_vlm_weights=false",
        "--policy.resize_imgs_with_padding=[64,64]",
        "--policy.train_expert_only=false",
        "--policy.freeze_vision_encoder=false",
        "--policy.chunk_size=16",
        "--policy.n_action_steps=16",
        "--policy.num_steps=2",
    ]
    run = [
        *("--policy.type=smolvla", "--policy.device=cpu", "--policy.push_to_hub=false"),
        *("--dataset.repo_id=synthetic/g1", f"--dataset.root={data}", "--dataset.video_backend=pyav"),
        *("--num_workers=0", "--batch_size=2", "--steps=1", "--save_freq=1", "--wandb.enable=false"),
        f"--output_dir={root / 'train'}",
    ]
    done = subprocess.run(
        [sys.executable, "-m", "mobilemani_vla.lerobot_train", *flags, *run],
        cwd=ROOT,
        env=checkout_env(HF_HUB_OFFLINE="1", WANDB_MODE="disabled"),
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr[-3000:]  # lerobot-train's traceback, not just its exit code
    return root / "train" / "checkpoints" / "last" / "pretrained_model"


def test_lerobot_smolvla_trained_offline_runs_through_the_harness(smolvla_dir):
    policy = LeRobotEvalPolicy(smolvla_dir)
    assert policy.name == "lerobot_smolvla" and policy.windowed and policy.image_size == (48, 64)
    # The run recorded its dataset's digest, which the evaluation's training record then carries.
    record = json.loads((smolvla_dir.parents[2] / "dataset.json").read_text())
    digest = dataset_digest("synthetic/g1", record["root"])
    assert policy.training["dataset_sha256"] == record["sha256"] == digest
    assert {HEAD_RGB, schema.STATE, "task"} <= policy.inputs and policy.action_dim == 7
    env = MobileManiEnv(
        EnvCfg(num_envs=2, seed=0, episode_length=6, task=TaskCfg(object="test/box", skill="open"))
    )
    stats = run_batch(env, policy, 0, "open box", EnsembleCfg(), image_size=policy.image_size)
    assert stats.length.max() <= 6 and stats.success.shape == (2,)
    rng = np.random.default_rng(0)
    obs = {k: rng.integers(0, 255, (3, 48, 64, 3), np.uint8) for k in policy.inputs if "images" in k}
    obs |= {
        schema.STATE: np.zeros((3, schema.state_dim(1)), np.float32),
        "task": ["open box"] * 3,
        "active": np.array([True, False, True]),
    }
    torch.manual_seed(0)
    chunks = policy.act(obs)
    assert chunks.shape == (3, 16, 7) and np.all(chunks[1] == 0) and np.all(np.isfinite(chunks))
    # The instruction reaches the VLM (tokenized by the local backbone's tokenizer): same noise, other chunks.
    torch.manual_seed(0)
    other = policy.act(obs | {"task": ["close drawer"] * 3})
    assert not np.allclose(chunks[0], other[0])


def test_lerobot_smolvla_needs_its_backbone_directory(smolvla_dir, tmp_path):
    import json

    config = json.loads((smolvla_dir / "config.json").read_text())
    (tmp_path / "config.json").write_text(json.dumps(config | {"vlm_model_name": str(tmp_path / "gone")}))
    with pytest.raises(FileNotFoundError, match="backbone directory"):
        LeRobotEvalPolicy(tmp_path)

"""The LeRobot policy plugin (integrations/lerobot_policy_mobilemanivla): `lerobot-train
--policy.type=mobilemanivla` trains the tiny preset on a LeRobot dataset, and its checkpoint runs in
`lerobot-eval` and in our harness."""

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from checkout import checkout_env
from lerobot_policy_mobilemanivla import MobileManiVLAConfig

from mobilemani_data import schema
from mobilemani_rl.utils.errors import InputError
from mobilemani_vla.data.synthetic import write_synthetic_dataset
from mobilemani_vla.eval.config import EvalCfg, PolicyCfg
from mobilemani_vla.eval.evaluate import evaluate
from mobilemani_vla.eval.policies.base import ACTIVE, TASK
from mobilemani_vla.eval.policies.lerobot import LeRobotEvalPolicy

HEIGHT, WIDTH = 32, 40
CAMERAS = "[head_rgb,wrist_rgb]"


def lerobot(command: str, *args: str, cwd) -> None:
    """LeRobot's console script `command` (installed beside this interpreter), as a user runs it."""
    script = str(Path(sys.executable).parent / command)
    done = subprocess.run(
        [script, *args], cwd=cwd, env=checkout_env(HF_HUB_OFFLINE="1"), capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr[-3000:]


@pytest.fixture(scope="module")
def checkpoint(tmp_path_factory):
    """Two lerobot-train steps of the tiny MobileManiVLA on the synthetic dataset."""
    tmp = tmp_path_factory.mktemp("mobilemanivla")
    data = write_synthetic_dataset(tmp / "data", episodes=2, length=20, height=HEIGHT, width=WIDTH)
    lerobot(
        "lerobot-train",
        "--policy.type=mobilemanivla",
        f"--policy.cameras={CAMERAS}",
        "--policy.overrides=[diffusion.ddim_steps=2]",
        "--policy.device=cpu",
        "--policy.push_to_hub=false",
        "--dataset.repo_id=synthetic/g1",
        f"--dataset.root={data}",
        "--dataset.video_backend=pyav",
        "--num_workers=0",
        "--batch_size=2",
        "--steps=2",
        "--save_freq=2",
        "--log_freq=1",
        "--wandb.enable=false",
        f"--output_dir={tmp / 'train'}",
        cwd=tmp,
    )
    return tmp / "train" / "checkpoints" / "last" / "pretrained_model"


def test_lerobot_train_writes_a_checkpoint_our_harness_runs(checkpoint, tmp_path):
    config = json.loads((checkpoint / "config.json").read_text())
    assert config["type"] == "mobilemanivla" and config["cameras"] == ["head_rgb", "wrist_rgb"]
    assert "open box" in config["tasks"] and config["vla_yaml"]
    policy = LeRobotEvalPolicy(checkpoint)
    training = dict(policy.training)
    assert re.fullmatch("[0-9a-f]{64}", training.pop("weights_sha256"))  # tells retrained weights apart
    assert training == {"model": "mobilemanivla", "steps": 2, "batch_size": 2, "samples": 4}
    n = 2
    obs = {
        k: np.zeros((n, HEIGHT, WIDTH, 3), np.uint8)
        for k in policy.inputs
        if k.startswith("observation.images")
    }
    obs |= {schema.STATE: np.zeros((n, schema.state_dim(1)), np.float32), TASK: ["open box"] * n}
    obs[ACTIVE] = np.ones(n, dtype=bool)
    chunks = policy.act(obs)
    assert chunks.shape == (n, 16, 7) and np.isfinite(chunks).all()
    cfg = EvalCfg(
        output_dir=str(tmp_path / "eval"),
        policy=PolicyCfg(kind="lerobot", checkpoint=str(checkpoint)),
        episodes_per_batch=1,
    )
    cfg.subset.objects, cfg.subset.skills, cfg.subset.episodes = ["test/box"], ["open"], 1
    cfg.subset.scenes_per_object, cfg.env.episode_length = 1, 4
    assert evaluate(cfg.check())["overall"]["episodes"] == 1


def test_lerobot_eval_runs_the_checkpoint_on_the_env(checkpoint, tmp_path):
    lerobot(
        "lerobot-eval",
        f"--policy.path={checkpoint}",
        "--policy.device=cpu",
        "--env.type=mobilemanibench",
        "--env.task=g1/test/box/open/unseen_unseen",
        "--env.scenes_per_object=1",
        f"--env.cameras={CAMERAS}",
        f"--env.observation_height={HEIGHT}",
        f"--env.observation_width={WIDTH}",
        "--env.episode_length=4",
        "--eval.n_episodes=1",
        "--eval.batch_size=1",
        f"--output_dir={tmp_path / 'eval'}",
        cwd=tmp_path,
    )
    overall = json.loads((tmp_path / "eval" / "eval_info.json").read_text())["overall"]
    assert overall["n_episodes"] == 1 and "pc_success" in overall


def test_policy_config_names_what_the_dataset_lacks():
    from lerobot.configs import FeatureType, PolicyFeature

    image = PolicyFeature(type=FeatureType.VISUAL, shape=(3, HEIGHT, WIDTH))
    cfg = MobileManiVLAConfig(
        device="cpu",
        cameras=["head_depth"],
        input_features={
            schema.image_key("head", "rgb"): image,
            schema.STATE: PolicyFeature(type=FeatureType.STATE, shape=(schema.state_dim(1),)),
        },
        output_features={schema.ACTION: PolicyFeature(type=FeatureType.ACTION, shape=(7,))},
    )
    with pytest.raises(InputError, match="policy.cameras"):
        cfg.validate_features()
    cfg.cameras = None
    cfg.validate_features()
    assert cfg.cameras == ["head_rgb"] and cfg.action_delta_indices == list(range(16))
    cfg.input_features[schema.image_key("wrist", "seg")] = image
    cfg.cameras = ["head_rgb", "wrist_seg"]  # a segmentation stream is an image input too
    cfg.validate_features()
    assert cfg.cameras == ["head_rgb", "wrist_seg"]
    cfg.overrides = ["inputs.states=[wrist_pose,grasp_point]"]
    cfg.vla_yaml = None
    with pytest.raises(InputError, match="grasp_point"):  # object.* features never reach a LeRobot policy
        cfg.validate_features()
    cfg.output_features[schema.ACTION] = PolicyFeature(type=FeatureType.ACTION, shape=(5,))
    with pytest.raises(InputError, match="width"):
        cfg.validate_features()

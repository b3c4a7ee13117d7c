"""GPU-path logic checked on a CPU: FSDP-format checkpoints load, pretrained weights load in the training
dtype, the evaluation policy's diffusion noise comes from a generator on the model's device, and multi-process
(DDP) training saves and resumes every rank."""

import json
import pickle
import shutil
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import torch
from checkout import checkout_env
from payload import PlantedCode
from safetensors.torch import load_file
from transformers import PaliGemmaForConditionalGeneration

from mobilemani_rl.utils.errors import InputError
from mobilemani_vla.checkpoint import EMA_WEIGHTS, FSDP_SHARDS, FSDP_WEIGHTS, WEIGHTS, load_checkpoint
from mobilemani_vla.config import ModelCfg, compose_vla_cfg
from mobilemani_vla.data.synthetic import write_synthetic_dataset
from mobilemani_vla.eval.policies.vla import VLAEvalPolicy
from mobilemani_vla.model.backbone import paligemma_config
from mobilemani_vla.model.network import build_model
from mobilemani_vla.model.tokenizer import build_word_tokenizer, load_tokenizer
from mobilemani_vla.train import check_main_process_features, train


@pytest.fixture(scope="module")
def checkpoint(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("gpu_paths")
    data = write_synthetic_dataset(root / "g1", episodes=2, length=20)
    cfg = compose_vla_cfg(
        [
            "vla/model=tiny",
            f"data.root={data}",
            "data.repo_id=synthetic/g1",
            "data.heldout_episodes=0",
            f"train.output_dir={root / 'run'}",
            "train.logger=none",
            "train.progress=false",
            "train.batch_size=4",
            "train.steps=2",
            "train.ema_decay=0",
            "train.diagnose_every=0",
        ]
    )
    return train(cfg).checkpoint


def test_fsdp_full_state_dict_checkpoint_loads_and_runs_no_code(checkpoint, tmp_path):
    fsdp = shutil.copytree(checkpoint, tmp_path / "fsdp")
    weights = load_file(fsdp / WEIGHTS)
    (fsdp / WEIGHTS).unlink()
    # what accelerate's save_state writes under FSDP (FULL_STATE_DICT)
    torch.save(weights, fsdp / FSDP_WEIGHTS)
    _, model, _, _ = load_checkpoint(fsdp)
    assert all(torch.equal(model.state_dict()[k], v) for k, v in weights.items())

    (fsdp / FSDP_WEIGHTS).write_bytes(pickle.dumps({"x": PlantedCode(tmp_path / "PWNED")}))
    with pytest.raises(pickle.UnpicklingError):  # weights_only=True refuses anything but tensors
        load_checkpoint(fsdp)
    assert not (tmp_path / "PWNED").exists()
    (fsdp / FSDP_WEIGHTS).unlink()
    (fsdp / FSDP_SHARDS).mkdir()
    with pytest.raises(FileNotFoundError, match="accelerate merge-weights"):
        load_checkpoint(fsdp)
    assert not (checkpoint / EMA_WEIGHTS).exists()  # these weights are the trained ones, not an average


DEVICES = ["cpu"] + (["cuda"] if torch.cuda.is_available() else [])


@pytest.mark.parametrize("on", DEVICES)
def test_pretrained_backbone_loads_in_the_configured_dtype_and_feeds_a_float32_head(tmp_path, on):
    torch.manual_seed(0)
    PaliGemmaForConditionalGeneration(paligemma_config(ModelCfg())).save_pretrained(tmp_path)
    build_word_tokenizer().save_pretrained(tmp_path)
    cfg = compose_vla_cfg(
        [f"model.pretrained_path={tmp_path}", f"model.tokenizer_path={tmp_path}", "model.dtype=bfloat16"]
    )
    model = build_model(cfg, load_tokenizer(tmp_path)).to(on)
    assert {p.dtype for p in model.backbone.vlm.parameters()} == {torch.bfloat16}
    assert {p.dtype for p in model.head.parameters()} == {torch.float32}
    size = model.backbone.image_size
    enc = build_word_tokenizer()(["open box"] * 2, return_tensors="pt")
    batch = {
        "pixel_values": torch.rand(2, 4, 3, size, size),
        "input_ids": enc["input_ids"],
        "attention_mask": enc["attention_mask"],
        "state": torch.zeros(2, 9),
        "actions": torch.rand(2, 16, 7),
    }
    loss = model({k: v.to(on) for k, v in batch.items()})
    assert loss.dtype == torch.float32 and torch.isfinite(loss)
    with pytest.raises(ValueError, match="model.dtype"):
        compose_vla_cfg(["model.dtype=int8"])


@pytest.mark.parametrize("on", DEVICES)
def test_evaluation_noise_generator_lives_on_the_model_device(checkpoint, on):
    policy = VLAEvalPolicy(checkpoint, on)
    policy.start(env=SimpleNamespace(num_envs=1), seed=3)
    device = next(policy.policy.model.parameters()).device
    assert policy.generator.device == device
    size = policy.policy.model.backbone.image_size
    images = {c: np.zeros((1, size, size, 3), np.uint8) for c in policy.policy.cameras}
    vectors = {k: np.zeros((1, 10), np.float32) for k in policy.policy.vector_inputs}
    first = policy.policy.predict_action_chunks(images, ["open box"], vectors, policy.generator)
    policy.start(env=SimpleNamespace(num_envs=1), seed=3)
    again = policy.policy.predict_action_chunks(images, ["open box"], vectors, policy.generator)
    assert np.array_equal(first, again)


@pytest.mark.slow
def test_two_process_training_saves_every_rank_and_resumes(tmp_path):
    """`accelerate launch --multi_gpu`'s path (DDP) on two CPU processes (torchrun, gloo): the batch splits
    over the ranks, every rank's state is in a checkpoint before it is published, and a rerun resumes both."""
    data = write_synthetic_dataset(tmp_path / "g1", episodes=2, length=20)
    run_dir = tmp_path / "run"
    torchrun = [sys.executable, "-m", "torch.distributed.run", "--standalone", "--nproc_per_node", "2"]
    launch = [*torchrun, "-m", "mobilemani_vla.train"]
    settings = [
        "vla/model=tiny",
        f"data.root={data}",
        "data.repo_id=synthetic/g1",
        "data.heldout_episodes=0",
        f"train.output_dir={run_dir}",
        "train.logger=none",
        "train.save_every=10",
        "train.batch_size=8",
        "train.progress=false",
    ]
    env = checkout_env(ACCELERATE_USE_CPU="1")
    for steps in (20, 30):
        done = subprocess.run(
            [*launch, *settings, f"train.steps={steps}"], env=env, capture_output=True, text=True, timeout=600
        )
        assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
        checkpoint = run_dir / "checkpoints" / f"step_{steps:08d}"
        assert sorted(p.name for p in checkpoint.glob("random_states_*.pkl")) == [
            "random_states_0.pkl",
            "random_states_1.pkl",
        ]
    last = json.loads((run_dir / "last_run.json").read_text())
    assert last["checkpoint"].endswith("step_00000030")
    assert len(last["losses"]) == 10 and np.isfinite(last["losses"]).all()  # the resumed run: steps 21-30


def test_sharded_fsdp_refuses_what_needs_the_whole_model_on_one_process():
    paper = compose_vla_cfg(["vla/train=paper"]).train  # no EMA; held-out diagnostics every 5000 steps
    with pytest.raises(InputError, match=r"train.diagnose_every=5000 need the whole model .* set them to 0"):
        check_main_process_features(paper, sharded=True)
    cpu = compose_vla_cfg([]).train
    with pytest.raises(InputError, match=r"train.ema_decay=.* and train.diagnose_every=500 need"):
        check_main_process_features(cpu, sharded=True)
    check_main_process_features(cpu, sharded=False)  # DDP and one process keep every feature
    check_main_process_features(
        compose_vla_cfg(["vla/train=paper", "train.diagnose_every=0"]).train, sharded=True
    )

"""Checkpoint directory layout (one per saved step, written under a temporary name and renamed when complete):

model.safetensors  optimizer.bin  random_states_*.pkl   accelerate's training state (weights unwrapped); under
                     FSDP accelerate writes pytorch_model_fsdp.bin instead and the trainer adds the gathered
                     weights as model.safetensors, so every checkpoint has one
ema.safetensors      the moving average of the weights (train.ema_decay > 0); evaluation loads these
config.yaml          the VLACfg
backbone_config.json the PaliGemma config, so reloading needs no pretrained directory
normalizer.json      per-dimension bounds of actions and states (training split)
dataset.json         the training dataset: root, episodes, recorded image size (height, width)
tokenizer/           the tokenizer
trainer_state.json   the step
"""

from __future__ import annotations

import json
import shutil
import zipfile
from pathlib import Path

import torch
from safetensors import safe_open
from safetensors.torch import load_file, load_model, save_file, save_model
from torch.optim.swa_utils import AveragedModel
from transformers import PaliGemmaConfig, PreTrainedTokenizerBase

from mobilemani_rl.utils.errors import InputError, MissingFileError
from mobilemani_rl.utils.io import read_json, weights_sha256
from mobilemani_vla.config import VLACfg, vla_cfg_from_yaml, vla_cfg_to_yaml
from mobilemani_vla.model.network import MobileManiVLA, build_model
from mobilemani_vla.model.normalizer import Normalizer
from mobilemani_vla.model.tokenizer import load_tokenizer

WEIGHTS = "model.safetensors"
FSDP_WEIGHTS = "pytorch_model_fsdp.bin"  # accelerate's save_state under FSDP with a FULL_STATE_DICT
FSDP_SHARDS = "pytorch_model_fsdp_0"  # ... and with a SHARDED_STATE_DICT (torch.distributed.checkpoint)
EMA_WEIGHTS = "ema.safetensors"
DATASET = "dataset.json"
STATE = "trainer_state.json"
PREFIX = "step_"
TRAINING_STATE = ("*.bin", "*.pkl")  # accelerate's torch.save archives: optimizer, scheduler, random states


def save_artifacts(
    directory: Path,
    cfg: VLACfg,
    model: MobileManiVLA,
    normalizer: Normalizer,
    tokenizer: PreTrainedTokenizerBase,
    step: int,
    dataset: dict,
    ema: AveragedModel | None = None,
) -> None:
    (directory / DATASET).write_text(json.dumps(dataset, indent=1))
    if ema is not None:
        save_model(ema, str(directory / EMA_WEIGHTS))
    (directory / "config.yaml").write_text(vla_cfg_to_yaml(cfg))
    model.backbone.vlm.config.to_json_file(directory / "backbone_config.json")
    normalizer.save(directory / "normalizer.json")
    tokenizer.save_pretrained(directory / "tokenizer")
    (directory / STATE).write_text(json.dumps({"step": step}))


def checkpoint_dir(output_dir: Path, step: int) -> Path:
    return output_dir / "checkpoints" / f"{PREFIX}{step:08d}"


def finished_checkpoints(output_dir: Path) -> list[Path]:
    """Complete checkpoints, oldest first (temporary directories are skipped)."""
    root = output_dir / "checkpoints"
    if not root.is_dir():
        return []
    return sorted(p for p in root.iterdir() if p.name.startswith(PREFIX) and (p / STATE).is_file())


def unreadable_weights(directory: Path) -> str | None:
    """Why one of a checkpoint's safetensors files cannot be read (a disk fault, a copy cut short), naming
    it; None when every header reads and matches the file's length."""
    for path in sorted(directory.glob("*.safetensors")):
        try:
            with safe_open(str(path), "pt") as weights:
                weights.keys()
        except Exception as err:  # safetensors raises its own error types for every kind of damage
            return f"{path}: {type(err).__name__}: {err}"
    return None


def unreadable_training_state(directory: Path) -> str | None:
    """Why one of accelerate's training-state archives cannot be opened, naming it; None when each is a whole
    zip archive (torch.save's format keeps its index at the end, so a copy cut short loses it)."""
    for path in sorted(p for pattern in TRAINING_STATE for p in directory.glob(pattern)):
        try:
            zipfile.ZipFile(path).close()
        except (zipfile.BadZipFile, OSError) as err:
            return f"{path}: {type(err).__name__}: {err}"
    return None


def check_weights(directory: Path) -> None:
    if (why := unreadable_weights(directory)) is not None:
        raise InputError(f"unreadable checkpoint weights {why}")


def publish(tmp: Path, final: Path, keep: int) -> None:
    """Rename a complete temporary checkpoint into place and drop the oldest beyond `keep`."""
    if final.exists():
        shutil.rmtree(final)
    tmp.rename(final)
    for old in finished_checkpoints(final.parent.parent)[:-keep]:
        shutil.rmtree(old)


def checkpoint_step(directory: Path) -> int:
    return read_json(directory / STATE)["step"]


def recorded_image_size(directory: str | Path) -> tuple[int, int] | None:
    """(height, width) of the training dataset's images, when the checkpoint recorded it."""
    path = Path(directory) / DATASET
    return tuple(read_json(path)["image_size"]) if path.is_file() else None


def training_scale(directory: str | Path, cfg: VLACfg) -> dict:
    """How much training a checkpoint holds, for the captions of result tables: its model preset, steps,
    batch, samples seen, training episodes and image size; the digest of its dataset, which tells rows
    trained on different demonstrations apart; and the digest of its weights, which tells a retrained model
    from the one whose results its directory holds."""
    directory = Path(directory)
    dataset = read_json(directory / DATASET)
    step = checkpoint_step(directory)
    return {
        "model": cfg.model.name,
        "steps": step,
        "batch_size": cfg.train.batch_size,
        "samples": step * cfg.train.batch_size,
        "train_episodes": len(dataset["train_episodes"]),
        "image_size": dataset.get("image_size"),
        "dataset_sha256": dataset.get("sha256"),
        "weights_sha256": weights_sha256(directory),
    }


def load_ema(ema: AveragedModel, directory: Path) -> None:
    """Restore a resumed run's moving average (weights and update count)."""
    load_model(ema, str(directory / EMA_WEIGHTS))


def save_gathered_weights(directory: Path, state: dict[str, torch.Tensor]) -> None:
    """Write the full (gathered) weights as model.safetensors where accelerate wrote another format (FSDP)."""
    if not (directory / WEIGHTS).is_file():
        save_file({k: v.contiguous() for k, v in state.items()}, str(directory / WEIGHTS))


def trained_weights(directory: Path) -> dict[str, torch.Tensor]:
    """model.safetensors, or accelerate's FSDP full state dict
    (tensors only: loaded with weights_only=True)."""
    if (directory / WEIGHTS).is_file():
        return load_file(directory / WEIGHTS)
    if (directory / FSDP_WEIGHTS).is_file():
        return torch.load(directory / FSDP_WEIGHTS, map_location="cpu", weights_only=True)
    if (directory / FSDP_SHARDS).is_dir():
        raise MissingFileError(
            f"{directory} holds sharded FSDP weights only; merge them first: accelerate "
            f"merge-weights {directory / FSDP_SHARDS} {directory}"
        )
    raise MissingFileError(
        f"{directory} is not a complete MobileManiVLA checkpoint (no {WEIGHTS} or {FSDP_WEIGHTS})"
    )


def load_checkpoint(
    directory: str | Path, device: str | torch.device = "cpu"
) -> tuple[VLACfg, MobileManiVLA, Normalizer, PreTrainedTokenizerBase]:
    """The evaluated model: the moving-average weights when the run kept them, else the trained ones."""
    directory = Path(directory)
    if not (directory / STATE).is_file():
        # a training run's output directory (or its checkpoints/) is the usual mistake: name what it holds
        found = finished_checkpoints(directory.parent if directory.name == "checkpoints" else directory)
        hint = f"; the newest of the {len(found)} it holds is {found[-1]}" if found else ""
        raise MissingFileError(f"{directory} is not a complete MobileManiVLA checkpoint (no {STATE}){hint}")
    check_weights(directory)
    cfg = vla_cfg_from_yaml((directory / "config.yaml").read_text())
    tokenizer = load_tokenizer(directory / "tokenizer")
    model = build_model(cfg, tokenizer, PaliGemmaConfig.from_json_file(directory / "backbone_config.json"))
    if (directory / EMA_WEIGHTS).is_file():
        prefix = "module."
        state = {
            k[len(prefix) :]: v for k, v in load_file(directory / EMA_WEIGHTS).items() if k.startswith(prefix)
        }
    else:
        state = trained_weights(directory)
    model.load_state_dict(state)
    return cfg, model.to(device).eval(), Normalizer.load(directory / "normalizer.json"), tokenizer

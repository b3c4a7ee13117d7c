"""Checkpoint directory layout (one per saved step, written under a temporary name and renamed when complete):

    model.safetensors  optimizer.bin  random_states_*.pkl   accelerate's training state (weights unwrapped)
    config.yaml          the VLACfg
    backbone_config.json the PaliGemma config, so reloading needs no pretrained directory
    normalizer.json      q01/q99 of actions and states
    tokenizer/           the tokenizer
    trainer_state.json   the step
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import torch
from safetensors.torch import load_file
from transformers import PaliGemmaConfig, PreTrainedTokenizerBase

from mobilemani_vla.config import VLACfg, vla_cfg_from_yaml, vla_cfg_to_yaml
from mobilemani_vla.model import MobileManiVLA, build_model
from mobilemani_vla.normalizer import QuantileNormalizer
from mobilemani_vla.tokenizer import load_tokenizer

WEIGHTS = "model.safetensors"
STATE = "trainer_state.json"
PREFIX = "step_"


def save_artifacts(directory: Path, cfg: VLACfg, model: MobileManiVLA, normalizer: QuantileNormalizer,
                   tokenizer: PreTrainedTokenizerBase, step: int) -> None:
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


def publish(tmp: Path, final: Path, keep: int) -> None:
    """Rename a complete temporary checkpoint into place and drop the oldest beyond `keep`."""
    if final.exists():
        shutil.rmtree(final)
    tmp.rename(final)
    for old in finished_checkpoints(final.parent.parent)[:-keep]:
        shutil.rmtree(old)


def checkpoint_step(directory: Path) -> int:
    return json.loads((directory / STATE).read_text())["step"]


def load_checkpoint(directory: str | Path, device: str | torch.device = "cpu"
                    ) -> tuple[VLACfg, MobileManiVLA, QuantileNormalizer, PreTrainedTokenizerBase]:
    directory = Path(directory)
    if not (directory / WEIGHTS).is_file() or not (directory / STATE).is_file():
        raise FileNotFoundError(f"{directory} is not a complete MobileManiVLA checkpoint (no {WEIGHTS} / {STATE})")
    cfg = vla_cfg_from_yaml((directory / "config.yaml").read_text())
    tokenizer = load_tokenizer(directory / "tokenizer")
    model = build_model(cfg, tokenizer, PaliGemmaConfig.from_json_file(directory / "backbone_config.json"))
    model.load_state_dict(load_file(directory / WEIGHTS))
    return cfg, model.to(device).eval(), QuantileNormalizer.load(directory / "normalizer.json"), tokenizer

"""Train MobileManiVLA: python -m mobilemani_vla.train [robot=g1] [vla/model=tiny] [+experiment=ablation_...].

Runs through `accelerate`: single process on a CPU; on GPUs `accelerate launch --multi_gpu -m mobilemani_vla.train
vla/model=paligemma2_3b vla/train=paper ...` (DDP, bf16 from train.mixed_precision), or an FSDP accelerate config
with `fsdp_state_dict_type: FULL_STATE_DICT` so that checkpoints hold one model.safetensors. Checkpoints
(safetensors + config + normaliser + tokenizer) go to train.output_dir/checkpoints; a run resumes from the
newest one there unless train.resume=false.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict, dataclass
from pathlib import Path

import hydra
import torch
from accelerate import Accelerator
from accelerate.utils import set_seed
from omegaconf import DictConfig
from torch.utils.data import DataLoader
from tqdm import tqdm

from mobilemani_data import schema
from mobilemani_vla.checkpoint import (
    checkpoint_dir,
    checkpoint_step,
    finished_checkpoints,
    publish,
    save_artifacts,
)
from mobilemani_vla.config import VLACfg, vla_cfg_from_hydra, vla_cfg_from_yaml
from mobilemani_vla.data import dataset_tasks, open_dataset
from mobilemani_vla.model import MobileManiVLA, build_model
from mobilemani_vla.normalizer import QuantileNormalizer
from mobilemani_vla.processor import STATE_KEYS, VLAProcessor
from mobilemani_vla.tokenizer import load_tokenizer


@dataclass
class TrainResult:
    losses: list[float]  # per step, this process's batch
    checkpoint: Path
    model: MobileManiVLA
    processor: VLAProcessor


def _batches(loader: DataLoader):
    """Endless iteration over epochs (the sampler reshuffles each epoch)."""
    while True:
        yield from loader


def _resume_point(cfg: VLACfg, output_dir: Path) -> Path | None:
    """The newest checkpoint to continue from; one of another model/input/diffusion setup is refused."""
    found = finished_checkpoints(output_dir) if cfg.train.resume else []
    if not found:
        return None
    saved = vla_cfg_from_yaml((found[-1] / "config.yaml").read_text())
    fields = ("robot", "model", "inputs", "diffusion")
    if any(getattr(saved, f) != getattr(cfg, f) for f in fields):
        raise ValueError(f"{found[-1]} was trained with a different {'/'.join(fields)} config; choose another "
                         "train.output_dir or set train.resume=false")
    return found[-1]


def train(cfg: VLACfg) -> TrainResult:
    os.environ.setdefault("WANDB_MODE", "offline")
    output_dir = Path(cfg.train.output_dir)
    accelerator = Accelerator(mixed_precision=cfg.train.mixed_precision, project_dir=str(output_dir),
                              log_with="wandb" if cfg.train.logger == "wandb" else None)
    set_seed(cfg.train.seed)
    per_device, rest = divmod(cfg.train.batch_size, accelerator.num_processes)
    if rest or per_device == 0:
        raise ValueError(f"train.batch_size={cfg.train.batch_size} must split evenly over "
                         f"{accelerator.num_processes} processes")

    dataset = open_dataset(cfg)
    resume_from = _resume_point(cfg, output_dir)
    if resume_from is not None:  # tokenizer and normaliser stay those the weights were trained with
        tokenizer = load_tokenizer(resume_from / "tokenizer")
        normalizer = QuantileNormalizer.load(resume_from / "normalizer.json")
    else:
        tokenizer = load_tokenizer(cfg.model.tokenizer_path, dataset_tasks(dataset))
        keys = [schema.ACTION_BASE] + [STATE_KEYS[s] for s in cfg.inputs.states]
        normalizer = QuantileNormalizer.from_stats(dataset.meta.stats, keys)

    model = build_model(cfg, tokenizer)
    if cfg.train.gradient_checkpointing:
        model.backbone.vlm.gradient_checkpointing_enable()
    processor = VLAProcessor(tokenizer, normalizer, cfg.inputs.cameras, cfg.inputs.states,
                             model.backbone.image_size, cfg.model.prompt)
    loader = DataLoader(dataset, batch_size=per_device, shuffle=True, collate_fn=processor,
                        num_workers=cfg.data.num_workers, drop_last=len(dataset) >= cfg.train.batch_size)
    optimizer = torch.optim.AdamW(model.parameters(), lr=cfg.train.lr, weight_decay=cfg.train.weight_decay)
    model, optimizer, loader = accelerator.prepare(model, optimizer, loader)

    start = 0
    if resume_from is not None:
        accelerator.load_state(str(resume_from))
        start = checkpoint_step(resume_from)
    accelerator.init_trackers("mobilemani_vla", config=asdict(cfg),
                              init_kwargs={"wandb": {"name": cfg.name, "dir": str(output_dir)}})

    def save(at: int) -> Path:
        final = checkpoint_dir(output_dir, at)
        tmp = final.with_name(f".tmp_{final.name}")
        accelerator.save_state(str(tmp))  # collective: every process takes part
        if accelerator.is_main_process:
            save_artifacts(tmp, cfg, accelerator.unwrap_model(model), normalizer, tokenizer, at)
            publish(tmp, final, cfg.train.keep_checkpoints)
        accelerator.wait_for_everyone()
        return final

    losses: list[float] = []
    model.train()
    batches = _batches(loader)
    bar = tqdm(range(start, cfg.train.steps), initial=start, total=cfg.train.steps, desc="vla",
               disable=not (cfg.train.progress and accelerator.is_local_main_process))
    for step in bar:
        loss = model(next(batches))
        accelerator.backward(loss)
        if cfg.train.grad_clip > 0:
            accelerator.clip_grad_norm_(model.parameters(), cfg.train.grad_clip)
        optimizer.step()
        optimizer.zero_grad(set_to_none=True)
        losses.append(loss.item())
        done = step + 1
        if done % cfg.train.log_every == 0:
            mean = accelerator.reduce(loss.detach(), reduction="mean").item()
            accelerator.log({"train/loss": mean}, step=done)
            bar.set_postfix(loss=f"{mean:.4f}")
        if done % cfg.train.save_every == 0 and done < cfg.train.steps:
            save(done)
    final = save(cfg.train.steps) if start < cfg.train.steps else resume_from
    accelerator.end_training()
    if accelerator.is_main_process:
        (output_dir / "last_run.json").write_text(json.dumps({"checkpoint": str(final), "losses": losses}))
    return TrainResult(losses, final, accelerator.unwrap_model(model), processor)


@hydra.main(config_path="../conf", config_name="vla", version_base="1.3")
def main(cfg: DictConfig) -> None:
    train(vla_cfg_from_hydra(cfg))


if __name__ == "__main__":
    main()

"""Train MobileManiVLA: python -m mobilemani_vla.train [robot=g1] [vla/model=tiny] [+experiment=ablation_...].

Runs through `accelerate`: single process on a CPU; on GPUs `accelerate launch --multi_gpu -m
mobilemani_vla.train vla/model=paligemma2_3b vla/train=paper ...` (DDP, bf16 from train.mixed_precision), or
an FSDP accelerate config (accelerate's FSDP files, plus the gathered weights as model.safetensors, which
evaluation loads; sharded FSDP runs without the weight EMA and the held-out diagnostics). Checkpoints
(safetensors + config + normaliser + tokenizer) go to train.output_dir/checkpoints; a run resumes from the
newest one there (train.resume=false: a new run only, refused where checkpoints are). The main process holds
train.output_dir/train.lock while it trains, so a second run on the directory stops at once. A
train.output_dir that cannot be written (a file in the way, a read-only file system) stops before the data is
read.
"""

from __future__ import annotations

import json
import os
import pickle
import time
from contextlib import ExitStack
from dataclasses import asdict, dataclass
from pathlib import Path

import hydra
import torch
from accelerate import Accelerator
from accelerate.utils import DistributedType, set_seed
from diffusers.optimization import get_scheduler
from omegaconf import DictConfig
from torch import nn
from torch.distributed.fsdp import ShardingStrategy
from torch.optim.lr_scheduler import LambdaLR
from torch.optim.swa_utils import AveragedModel
from torch.utils.data import DataLoader
from tqdm import tqdm
from transformers import PreTrainedTokenizerBase

from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_rl.utils.errors import InputError, OutputExistsError, first_sentence
from mobilemani_rl.utils.io import check_writable
from mobilemani_rl.utils.video_logs import quiet_video_libraries
from mobilemani_rl.utils.writer_lock import TRAIN_LOCK, WriterLock, busy
from mobilemani_vla.checkpoint import (
    checkpoint_dir,
    checkpoint_step,
    finished_checkpoints,
    load_ema,
    publish,
    save_artifacts,
    save_gathered_weights,
    unreadable_training_state,
    unreadable_weights,
)
from mobilemani_vla.config import ROOT_ONLY, TrainCfg, VLACfg, vla_cfg_from_yaml
from mobilemani_vla.data.augment import augment_images
from mobilemani_vla.data.dataset import fit_normalizer, open_data, open_metadata
from mobilemani_vla.diagnostics import diagnose, heldout_batch
from mobilemani_vla.model.network import MobileManiVLA, build_model
from mobilemani_vla.model.normalizer import Normalizer
from mobilemani_vla.model.processor import VLAProcessor
from mobilemani_vla.model.tokenizer import load_tokenizer


@dataclass
class TrainResult:
    losses: list[float]  # per step, this process's batch
    checkpoint: Path
    model: MobileManiVLA
    processor: VLAProcessor


def shards_weights(accelerator: Accelerator) -> bool:
    """Whether FSDP splits the weights over the processes, leaving the main process only its part."""
    if accelerator.distributed_type != DistributedType.FSDP or accelerator.num_processes == 1:
        return False
    plugin = accelerator.state.fsdp_plugin
    return plugin.fsdp_version == 2 or plugin.sharding_strategy != ShardingStrategy.NO_SHARD


def check_main_process_features(train_cfg: TrainCfg, sharded: bool) -> None:
    """The weight EMA and the held-out diagnostics run on the main process's copy of the whole model; with
    sharded weights the one would average a shard and the other hang or fail the first time it runs."""
    if not sharded:
        return
    used = [
        f"train.{k}={v}"
        for k, v in (("ema_decay", train_cfg.ema_decay), ("diagnose_every", train_cfg.diagnose_every))
        if v > 0
    ]
    if used:
        raise InputError(
            f"{' and '.join(used)} need the whole model on the main process, and FSDP shards it over the "
            "processes: set them to 0 (the paper's preset keeps no EMA), or train with DDP or FSDP's NO_SHARD"
        )


def _batches(loader: DataLoader):
    """Endless iteration over epochs (the sampler reshuffles each epoch)."""
    while True:
        yield from loader


def _resume_point(cfg: VLACfg, output_dir: Path) -> Path | None:
    """The newest readable checkpoint to continue from (one with unreadable weights or training state is named
    and skipped); one of another model/input/diffusion setup or of other training data is refused."""
    found = finished_checkpoints(output_dir)
    # A new run's checkpoints beside an earlier run's would be resumed as one run.
    if found and not cfg.train.resume:
        raise OutputExistsError(
            f"train.resume=false starts a new run, but {output_dir / 'checkpoints'} holds {found[-1].name} "
            "of an earlier one; choose another train.output_dir or delete its checkpoints"
        )
    if not found:
        return None
    saved = vla_cfg_from_yaml((found[-1] / "config.yaml").read_text())
    fields = ("robot", "model", "inputs", "diffusion")
    differing = [f for f in fields if getattr(saved, f) != getattr(cfg, f)]
    if _training_data(saved) != _training_data(cfg):
        differing.append("data")
    if differing:
        raise InputError(
            f"{found[-1]} was trained with a different {'/'.join(differing)} config; choose another "
            "train.output_dir or delete its checkpoints to start over"
        )
    if (reached := checkpoint_step(found[-1])) > cfg.train.steps:  # it would hand back a longer run's weights
        raise InputError(
            f"train.steps={cfg.train.steps}, but {found[-1]} is further on; only train.steps may grow, so "
            f"ask for {reached} or more, choose another train.output_dir or delete its checkpoints"
        )
    for checkpoint in reversed(found):
        if (why := unreadable_weights(checkpoint) or unreadable_training_state(checkpoint)) is None:
            return checkpoint
        print(f"skipping an unreadable checkpoint: {why}", flush=True)
    raise InputError(
        f"no readable checkpoint in {output_dir / 'checkpoints'}; delete the damaged ones named above "
        "to start over"
    )


def _training_data(cfg: VLACfg) -> tuple:
    """What decides the samples a run learns from; caching, decoding and loader workers do not."""
    data = cfg.data
    return Path(data.root).resolve(), data.repo_id, data.episodes, data.heldout_episodes


def _load_resume_artifacts(
    resume_from: Path | None, cfg: VLACfg, tasks: list[str]
) -> tuple[PreTrainedTokenizerBase, Normalizer | None]:
    """The tokenizer (and normaliser) a resumed run keeps; a new run builds its tokenizer."""
    if resume_from is not None:
        return load_tokenizer(resume_from / "tokenizer"), Normalizer.load(resume_from / "normalizer.json")
    return load_tokenizer(cfg.model.tokenizer_path, tasks), None


def ema_update(decay: float):
    """EMA step over all weights at once, with the usual warm-up, decay min(decay, (1 + n) / (10 + n)) after
    n updates, so a short run's average is not dominated by its random initial weights."""

    def update(averages: list[torch.Tensor], currents: list[torch.Tensor], n: torch.Tensor) -> None:
        d = min(decay, (1.0 + float(n)) / (10.0 + float(n)))
        torch._foreach_lerp_(averages, currents, 1.0 - d)  # one fused op, as torch's own EMA helper does

    return update


def adamw(model: nn.Module, cfg: TrainCfg) -> torch.optim.AdamW:
    """AdamW with its fused kernel (a per-tensor loop costs a small model's CPU step more than the update).
    With train.backbone_hold_steps, two parameter groups: the backbone's, then the rest (the action head, the
    state encoder); else one, which FSDP's flattened parameters and earlier runs' optimiser states expect."""
    params = list(model.parameters())
    if cfg.backbone_hold_steps > 0:
        backbone = list(model.backbone.parameters())
        held = {id(p) for p in backbone}
        params = [{"params": backbone}, {"params": [p for p in params if id(p) not in held]}]
    return torch.optim.AdamW(params, lr=cfg.lr, weight_decay=cfg.weight_decay, fused=True)


def lr_schedule(optimizer: torch.optim.AdamW, cfg: TrainCfg) -> LambdaLR:
    """train.lr_schedule; with train.backbone_hold_steps, the backbone's group (the first of `adamw`'s two) is
    at zero for those steps, then warms up linearly over train.warmup_steps."""
    schedule = get_scheduler(
        cfg.lr_schedule, optimizer, num_warmup_steps=cfg.warmup_steps, num_training_steps=cfg.steps
    )
    if cfg.backbone_hold_steps == 0:
        return schedule
    base = schedule.lr_lambdas[0]

    def backbone(step: int) -> float:
        released = step - cfg.backbone_hold_steps
        return base(step) * min(1.0, max(0.0, released / max(cfg.warmup_steps, 1)))

    return LambdaLR(optimizer, [backbone, base])


def piece_over(cfg: TrainCfg, start: float, accelerator: Accelerator) -> bool:
    """Whether this run's piece (train.piece_minutes) is used up; every process stops at the same step."""
    if cfg.piece_minutes <= 0:
        return False
    over = float(time.perf_counter() - start > 60 * cfg.piece_minutes)
    return accelerator.reduce(torch.tensor(over, device=accelerator.device), reduction="sum").item() > 0


def trim_diagnostics(path: Path, start: int) -> None:
    """Drop the diagnostics a killed run wrote after the checkpoint this run resumes from (start > 0), or all
    of them when it starts afresh (start == 0: it measures step 0 again)."""
    if path.is_file():
        lines = path.read_text().splitlines() if start > 0 else []
        path.write_text("".join(line + "\n" for line in lines if json.loads(line)["step"] <= start))


def train(cfg: VLACfg) -> TrainResult:
    with ExitStack() as held:  # the output directory's writer lock, from when it is made to the end
        return _train(cfg, held)


def _train(cfg: VLACfg, held: ExitStack) -> TrainResult:
    os.environ.setdefault("WANDB_MODE", "offline")
    output_dir = check_writable(cfg.train.output_dir, "train.output_dir")
    accelerator = Accelerator(
        mixed_precision=cfg.train.mixed_precision,
        project_dir=str(output_dir),
        log_with="wandb" if cfg.train.logger == "wandb" else None,
    )
    set_seed(cfg.train.seed)
    check_main_process_features(cfg.train, shards_weights(accelerator))
    per_device, rest = divmod(cfg.train.batch_size, accelerator.num_processes)
    if rest or per_device == 0:
        raise InputError(
            f"train.batch_size={cfg.train.batch_size} must split evenly over "
            f"{accelerator.num_processes} processes"
        )

    resume_from = _resume_point(cfg, output_dir)
    tokenizer, normalizer = _load_resume_artifacts(resume_from, cfg, sorted(open_metadata(cfg).tasks.index))
    model = build_model(cfg, tokenizer)
    if cfg.train.gradient_checkpointing:
        model.backbone.vlm.gradient_checkpointing_enable()
    with accelerator.main_process_first():  # one process builds the frame cache
        data = open_data(cfg, model.backbone.image_size, progress=accelerator.is_local_main_process)
    if normalizer is None:
        normalizer = fit_normalizer(data.table, data.table.rows(data.train_episodes), cfg.read_states)
    processor = VLAProcessor.for_config(cfg, tokenizer, normalizer, model.backbone.image_size)
    dataset_info = {
        "root": cfg.data.root,
        "sha256": data.table.digest(),
        "train_episodes": data.train_episodes.tolist(),
        "heldout_episodes": data.heldout_episodes.tolist(),
        "image_size": data.image_size,
    }
    loader = DataLoader(
        data.train,
        batch_size=per_device,
        shuffle=True,
        collate_fn=processor,
        num_workers=cfg.data.num_workers,
        drop_last=len(data.train) >= cfg.train.batch_size,
    )
    optimizer = adamw(model, cfg.train)
    schedule = lr_schedule(optimizer, cfg.train)
    model, optimizer, loader, schedule = accelerator.prepare(model, optimizer, loader, schedule)
    ema = (
        AveragedModel(accelerator.unwrap_model(model), multi_avg_fn=ema_update(cfg.train.ema_decay))
        if cfg.train.ema_decay > 0
        else None
    )

    start = 0
    if resume_from is not None:
        try:
            accelerator.load_state(str(resume_from))
        except pickle.UnpicklingError as err:  # accelerate loads with weights_only=True: not only tensors
            raise InputError(f"refusing the training state in {resume_from}: {first_sentence(err)}") from err
        start = checkpoint_step(resume_from)
        if ema is not None:
            load_ema(ema, resume_from)
    if cfg.train.compile:  # in place, after the average copied the model: its keys and copies stay plain
        accelerator.unwrap_model(model).compile()
    # Every input is checked by now; the run directory is made here, not by Hydra before the checks.
    output_dir.mkdir(parents=True, exist_ok=True)
    if accelerator.is_main_process:
        lock = WriterLock(output_dir / TRAIN_LOCK, busy("training run", output_dir, "train.output_dir"))
        held.enter_context(lock)
    accelerator.init_trackers(
        "mobilemani_vla",
        config=asdict(cfg),
        init_kwargs={"wandb": {"name": cfg.name, "dir": str(output_dir)}},
    )
    diagnostics_log = output_dir / "diagnostics.jsonl"
    diagnose_batch = None
    if accelerator.is_main_process and cfg.train.diagnose_every > 0 and data.heldout is not None:
        trim_diagnostics(diagnostics_log, start)
        diagnose_batch = {
            k: v.to(accelerator.device)
            for k, v in heldout_batch(data.heldout, cfg.train.diagnose_frames, processor).items()
        }

    def evaluated_model() -> MobileManiVLA:
        return ema.module if ema is not None else accelerator.unwrap_model(model)

    def run_diagnostics(at: int) -> None:
        if diagnose_batch is None:
            return
        values = diagnose(evaluated_model(), diagnose_batch, cfg.train.diagnose_cfg_scales)
        if window := losses[-cfg.train.diagnose_every :]:  # the training curve beside the held-out one
            values["train_loss"] = sum(window) / len(window)
        accelerator.log({f"diag/{k}": v for k, v in values.items()}, step=at)
        with diagnostics_log.open("a") as f:
            f.write(json.dumps({"step": at, **values}) + "\n")
        bar.write(f"step {at} held-out: " + " ".join(f"{k}={v:.4f}" for k, v in values.items()))

    def save(at: int) -> Path:
        final = checkpoint_dir(output_dir, at)
        tmp = final.with_name(f".tmp_{final.name}")
        accelerator.save_state(str(tmp))  # every process writes its part (its RNG state, FSDP shards)
        weights = accelerator.get_state_dict(model)  # FSDP: collective, gathers the shards on the main one
        # save_state ends without a barrier: publishing before every process has written would move the
        # directory from under a process still writing into it.
        accelerator.wait_for_everyone()
        if accelerator.is_main_process:
            save_gathered_weights(tmp, weights)
            save_artifacts(
                tmp, cfg, accelerator.unwrap_model(model), normalizer, tokenizer, at, dataset_info, ema
            )
            publish(tmp, final, cfg.train.keep_checkpoints)
        accelerator.wait_for_everyone()
        return final

    losses: list[float] = []
    model.train()
    batches = _batches(loader)
    bar = tqdm(
        range(start, cfg.train.steps),
        initial=start,
        total=cfg.train.steps,
        desc="vla",
        disable=not (cfg.train.progress and accelerator.is_local_main_process),
    )
    if start == 0:
        run_diagnostics(0)  # the untrained model's, the reference for how its features change
    clock = piece_start = time.perf_counter()
    for step in bar:
        batch = next(batches)
        batch["pixel_values"] = augment_images(batch["pixel_values"], cfg.inputs.cameras, cfg.train.augment)
        loss = model(batch)
        accelerator.backward(loss)
        if cfg.train.grad_clip > 0:
            accelerator.clip_grad_norm_(model.parameters(), cfg.train.grad_clip)
        optimizer.step()
        schedule.step()
        optimizer.zero_grad(set_to_none=True)
        if ema is not None:
            ema.update_parameters(accelerator.unwrap_model(model))
        losses.append(loss.item())
        done = step + 1
        if done % cfg.train.log_every == 0:
            mean = accelerator.reduce(loss.detach(), reduction="mean").item()
            rate = cfg.train.log_every * cfg.train.batch_size / (time.perf_counter() - clock)
            accelerator.log(
                {"train/loss": mean, "train/lr": schedule.get_last_lr()[-1], "train/samples_per_s": rate},
                step=done,
            )
            bar.set_postfix(loss=f"{mean:.4f}", samples_per_s=f"{rate:.1f}")
            clock = time.perf_counter()
        if cfg.train.diagnose_every > 0 and done % cfg.train.diagnose_every == 0:
            run_diagnostics(done)
        if done % cfg.train.save_every == 0 and done < cfg.train.steps:
            save(done)
        if piece_over(cfg.train, piece_start, accelerator) and done < cfg.train.steps:
            if cfg.train.diagnose_every > 0 and done % cfg.train.diagnose_every:
                run_diagnostics(done)  # each piece's curve ends where its checkpoint is
            if done % cfg.train.save_every:
                save(done)
            accelerator.end_training()
            print(f"train.piece_minutes reached at step {done}: a rerun resumes from here", flush=True)
            return TrainResult(losses, checkpoint_dir(output_dir, done), evaluated_model(), processor)
    final = save(cfg.train.steps) if start < cfg.train.steps else resume_from
    accelerator.end_training()
    if accelerator.is_main_process:
        (output_dir / "last_run.json").write_text(json.dumps({"checkpoint": str(final), "losses": losses}))
        print(f"checkpoint: {final}", flush=True)
    return TrainResult(losses, final, evaluated_model(), processor)


@hydra.main(config_path="../conf", config_name="vla", version_base="1.3")
@entry_point
def main(cfg: DictConfig) -> None:
    quiet_video_libraries()
    train(to_dataclass(cfg, VLACfg, ignore=ROOT_ONLY).validate())


if __name__ == "__main__":
    main()

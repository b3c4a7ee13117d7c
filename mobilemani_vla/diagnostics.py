"""Held-out diagnostics that tell whether the VLA uses its images and how well it predicts actions.

- Noise-prediction error with paired noise and timesteps: with the real cognition feature, with the learned
  null vector in its place (the classifier-free-guidance "unconditional" input), without the state feature,
  and with the instruction left empty or replaced by a wrong one. If the first is not clearly below the
  null vector's, the action head ignores what the backbone sees; if it is not below the empty and wrong
  instructions', the model does not read the instruction.
- Open-loop action error: DDIM-sampled chunks (clipped to [-1, 1] as when executed) against the recorded ones
  (normalised units, whole chunk and first step), for each classifier-free-guidance scale asked for, and the
  chunk sampled from the null vector alone: the noise error barely depends on any input, as a denoiser tells
  white noise from a smooth chunk without one, so this gap shows better how far the actions follow the images.
- The cognition feature's dependence on the input (`cognition_spread`): how much it varies from frame to frame
  and how much it moves when the frames' images are swapped, relative to its size. A backbone whose feature
  no longer depends on its input (spread 0) leaves the action head only the state.
- With cognition targets (`train.cognition_targets`), the read-out's error on them (`cognition/target_mse`).
"""

from __future__ import annotations

import numpy as np
import torch
import torch.nn.functional as F

from mobilemani_rl.assets.objects import ALL_SKILLS
from mobilemani_vla.model.network import MobileManiVLA
from mobilemani_vla.model.processor import VLAProcessor

SEED = 0  # fixed noise and timesteps, so successive diagnostics are comparable
INSTRUCTION_VARIANTS = ("null_instruction", "wrong_instruction")


def wrong_instructions(tasks: list[str]) -> list[str]:
    """Each instruction replaced by another one of the batch; with a single one (a single-task dataset), its
    skill word by the next skill's ("open box" -> "close box")."""
    distinct = sorted(set(tasks))
    if len(distinct) > 1:
        return [distinct[(distinct.index(t) + 1) % len(distinct)] for t in tasks]
    skill, _, rest = tasks[0].partition(" ")
    other = ALL_SKILLS[(ALL_SKILLS.index(skill) + 1) % len(ALL_SKILLS)] if skill in ALL_SKILLS else "open"
    return [f"{other} {rest}"] * len(tasks)


def heldout_batch(dataset, frames: int, processor: VLAProcessor) -> dict[str, torch.Tensor]:
    """A fixed, evenly spaced choice of `frames` held-out frames, collated, with the prompt tokens of the
    instruction variants beside the real ones (`<variant>/input_ids`, `<variant>/attention_mask`)."""
    picks = np.unique(np.linspace(0, len(dataset) - 1, num=min(frames, len(dataset))).round().astype(int))
    items = [dataset[int(i)] for i in picks]
    batch = processor(items)
    tasks = [item["task"] for item in items]
    for variant, texts in zip(
        INSTRUCTION_VARIANTS, ([""] * len(tasks), wrong_instructions(tasks)), strict=True
    ):
        batch.update({f"{variant}/{k}": v for k, v in processor.tokenize(texts).items()})
    return batch


@torch.no_grad()
def cognition_spread(
    model: MobileManiVLA, batch: dict[str, torch.Tensor], feature: torch.Tensor | None = None
) -> dict[str, float]:
    """Over the batch's frames, the cognition feature's mean per-dimension standard deviation and its RMS
    change when every frame's images are replaced by another frame's (a fixed derangement), both over its
    RMS. `feature`: the batch's cognition feature where the caller has it already."""
    prompt = batch["input_ids"], batch["attention_mask"]
    if feature is None:
        feature = model.backbone(batch["pixel_values"], *prompt)
    feature = feature.float()
    others = torch.roll(torch.arange(len(feature)), 1)
    swapped = model.backbone(batch["pixel_values"][others], *prompt).float()
    size = feature.pow(2).mean().sqrt().clamp(min=torch.finfo(feature.dtype).tiny)
    return {
        "cognition/spread": (feature.std(0).mean() / size).item(),
        "cognition/image_swap": ((feature - swapped).pow(2).mean().sqrt() / size).item(),
    }


@torch.no_grad()
def diagnose(
    model: MobileManiVLA, batch: dict[str, torch.Tensor], cfg_scales: list[float]
) -> dict[str, float]:
    was_training = model.training
    model.eval()
    head, actions = model.head, batch["actions"]
    cognition, state = model.condition(batch)
    generator = torch.Generator(device=actions.device).manual_seed(SEED)
    t = torch.randint(
        0, head.cfg.train_timesteps, (actions.shape[0],), generator=generator, device=actions.device
    )
    noise = torch.randn(actions.shape, generator=generator, device=actions.device)
    noisy = head.scheduler.add_noise(actions, noise, t)

    def noise_error(use_state: bool, null: bool, feature: torch.Tensor = cognition) -> float:
        drop = torch.ones(actions.shape[0], dtype=torch.bool, device=actions.device) if null else None
        pred = head.dit(noisy, t, feature, state if use_state else None, drop)
        return F.mse_loss(pred.float(), noise).item()

    out = {"noise_mse/image": noise_error(True, False)}
    if head.guided:
        out["noise_mse/null_image"] = noise_error(True, True)
    if state is not None:
        out["noise_mse/no_state"] = noise_error(False, False)
    for variant in INSTRUCTION_VARIANTS:
        if f"{variant}/input_ids" in batch:
            prompt = {k: batch[f"{variant}/{k}"] for k in ("input_ids", "attention_mask")}
            out[f"noise_mse/{variant}"] = noise_error(True, False, model.condition({**batch, **prompt})[0])

    def sampled_chunk(**guidance) -> torch.Tensor:
        """A DDIM chunk from the fixed noise, clipped to [-1, 1] as executed."""
        generator = torch.Generator(device=actions.device).manual_seed(SEED)
        return head.sample(cognition, state, model.action_dim, generator, **guidance).clamp(-1.0, 1.0)

    for scale in cfg_scales:
        sampled = sampled_chunk(cfg_scale=scale)
        out[f"open_loop_mse/cfg_{scale:g}"] = F.mse_loss(sampled.float(), actions).item()
        out[f"open_loop_mse_first/cfg_{scale:g}"] = F.mse_loss(sampled[:, 0].float(), actions[:, 0]).item()
    if head.guided:
        blind = sampled_chunk(unconditional=True)
        out["open_loop_mse/null_image"] = F.mse_loss(blind.float(), actions).item()
    out.update(cognition_spread(model, batch, cognition))
    if model.cognition_probe is not None:
        out["cognition/target_mse"] = model.cognition_target_error(cognition, batch).item()
    model.train(was_training)
    return out

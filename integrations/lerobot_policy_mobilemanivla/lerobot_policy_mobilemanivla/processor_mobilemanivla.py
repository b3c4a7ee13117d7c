"""LeRobot's pipelines for MobileManiVLA: rename, batch and move to the device on the way in, back to the CPU
on the way out. Normalisation is the config's IDENTITY for every feature: the model normalises with its own
bounds (modeling_mobilemanivla), so the batch keeps the dataset's units, images in [0, 1] and the
instruction."""

from __future__ import annotations

from typing import Any

import torch
from lerobot.processor import PolicyAction, PolicyProcessorPipeline, make_default_pre_post_processors

from lerobot_policy_mobilemanivla.configuration_mobilemanivla import MobileManiVLAConfig


def make_mobilemanivla_pre_post_processors(
    config: MobileManiVLAConfig, dataset_stats: dict[str, dict[str, torch.Tensor]] | None = None
) -> tuple[
    PolicyProcessorPipeline[dict[str, Any], dict[str, Any]],
    PolicyProcessorPipeline[PolicyAction, PolicyAction],
]:
    return make_default_pre_post_processors(config, dataset_stats, normalizer_device=config.device)

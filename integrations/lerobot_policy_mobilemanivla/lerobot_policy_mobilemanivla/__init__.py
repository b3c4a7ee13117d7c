"""MobileManiVLA (PaliGemma backbone, cognition token, DiT action head, adaptive ensemble) as a LeRobot
policy: `lerobot-train --policy.type=mobilemanivla`, then
`lerobot-eval --policy.path=<output_dir>/checkpoints/last/pretrained_model`. LeRobot finds the modelling and
processor modules beside the config by their names."""

from lerobot_policy_mobilemanivla.configuration_mobilemanivla import MobileManiVLAConfig

__all__ = ["MobileManiVLAConfig"]

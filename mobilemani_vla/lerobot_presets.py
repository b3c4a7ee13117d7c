"""The project's settings for stock LeRobot policies trained with `lerobot-train` on a CPU
(`python -m mobilemani_vla.lerobot_train --preset=cpu ...`, `make lerobot`, the ablation study's baselines).

Our action chunk is 16 steps at 30 Hz and the evaluation harness gives single observation steps, uncropped.
Nothing is downloaded: no pretrained backbone weights, and SmolVLA trains whole from scratch on an untrained
local SmolVLM backbone (`mobilemani_vla.smolvla_backbone`), written before training where it is missing; its
checkpoints name that directory, so it stays where it is. Diffusion Policy is sized for a CPU (LeRobot's
default U-Net and its 100 denoising steps per chunk are a GPU's). A flag given on the command line replaces
the preset's flag for the same key.
"""

from __future__ import annotations

from pathlib import Path

from mobilemani_rl.utils.errors import InputError

SMOLVLM_DIR = Path("outputs/lerobot/smolvlm")
RUN_FLAGS = [
    "--policy.device=cpu",
    "--policy.push_to_hub=false",
    "--dataset.video_backend=pyav",
    "--num_workers=0",
    "--wandb.enable=false",
]
POLICY_FLAGS = {
    "act": [
        "--policy.pretrained_backbone_weights=null",
        "--policy.chunk_size=16",
        "--policy.n_action_steps=16",
    ],
    "diffusion": [
        "--policy.pretrained_backbone_weights=null",
        "--policy.n_obs_steps=1",
        "--policy.horizon=16",
        "--policy.n_action_steps=8",
        "--policy.crop_shape=null",
        "--policy.down_dims=[128,256,512]",
        "--policy.num_inference_steps=10",
    ],
    "smolvla": [
        "--policy.load_vlm_weights=false",
        "--policy.resize_imgs_with_padding=[128,128]",
        "--policy.train_expert_only=false",
        "--policy.freeze_vision_encoder=false",
        "--policy.chunk_size=16",
        "--policy.n_action_steps=16",
    ],
}
PRESETS = ("cpu",)


def flag_key(arg: str) -> str | None:
    """`--policy.chunk_size=16` -> `policy.chunk_size`; None for a value."""
    return arg[2:].split("=", 1)[0] if arg.startswith("--") else None


def merge_flags(base: list[str], given: list[str]) -> list[str]:
    """`base` (`--key=value` flags) less the keys `given` names, then `given`: one flag per key, so that
    LeRobot's parser never sees a key twice."""
    keys = {key for arg in given if (key := flag_key(arg))}
    return [flag for flag in base if flag_key(flag) not in keys] + given


def preset_flags(preset: str, policy: str | None) -> list[str]:
    """The preset's flags for the policy type."""
    if preset not in PRESETS:
        raise InputError(f"--preset={preset}: choose among {', '.join(PRESETS)}")
    if policy not in POLICY_FLAGS:
        raise InputError(
            f"--preset={preset} needs --policy.type among {', '.join(POLICY_FLAGS)} (given: {policy})"
        )
    vlm = [smolvlm_flag()] if policy == "smolvla" else []
    return [*RUN_FLAGS, *POLICY_FLAGS[policy], *vlm]


def smolvlm_flag() -> str:
    """The preset's SmolVLA backbone, as an absolute path: its checkpoints name it."""
    return f"--policy.vlm_model_name={SMOLVLM_DIR.resolve()}"


def ensure_smolvlm_backbone(argv: list[str]) -> None:
    """Writes the preset's untrained SmolVLM backbone where `argv` names it and it is missing."""
    if smolvlm_flag() in argv and not (SMOLVLM_DIR / "config.json").exists():
        from mobilemani_vla.smolvla_backbone import write_smolvlm_backbone

        print(f"writing the untrained SmolVLM backbone to {write_smolvlm_backbone(SMOLVLM_DIR)}", flush=True)

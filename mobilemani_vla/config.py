"""Dataclass configs of MobileManiVLA: VLARootCfg is conf/vla.yaml's schema, whose groups (conf/vla/model,
conf/vla/train, conf/experiment) change the defaults. A composed config converts with
`to_dataclass(cfg, VLACfg, ignore=ROOT_ONLY).validate()`."""

from __future__ import annotations

from dataclasses import dataclass, field

from hydra import compose, initialize_config_dir
from omegaconf import OmegaConf

from mobilemani_data import schema
from mobilemani_rl.envs.config import RobotChoiceCfg
from mobilemani_rl.utils.config_store import CONF_DIR, register_schema, to_dataclass
from mobilemani_rl.utils.errors import InputError, check_positive, check_values
from mobilemani_vla.data.augment import AugmentCfg
from mobilemani_vla.model.dit import DIT_PRESETS, GELU_APPROXIMATIONS

DTYPES = ("float32", "bfloat16", "float16")
ROBOT_ACTION_DIMS = {"g1": 7, "xhand": 18}  # 6 wrist deltas + 1 gripper / 12 hand joints
CAMERAS = ("head_rgb", "head_depth", "wrist_rgb", "wrist_depth")  # the paper's image inputs
# Every image stream a dataset can hold: the paper's four and the segmentation images (object 1, robot 2,
# background 0), which show where the object is whatever the room looks like.
IMAGE_STREAMS = schema.IMAGE_STREAMS
STATES = ("wrist_pose", "grasp_point", "goal_point")
BETA_SCHEDULES = ("linear", "scaled_linear", "squaredcos_cap_v2")  # those diffusers' DDIMScheduler computes
VIDEO_BACKENDS = ("pyav", "torchcodec")  # LeRobot's decoders (its third, video_reader, is an alias of pyav)


@dataclass
class VisionCfg:
    """SigLIP vision tower (used when the backbone is built from this config rather than loaded)."""

    hidden_size: int = 32
    intermediate_size: int = 64
    num_hidden_layers: int = 2
    num_attention_heads: int = 2
    image_size: int = 32
    patch_size: int = 8
    hidden_act: str = "gelu_pytorch_tanh"  # SigLIP's; "gelu" (exact) is faster on CPUs, free from scratch


@dataclass
class TextCfg:
    """Gemma-2 language model (used when the backbone is built from this config rather than loaded)."""

    vocab_size: int = 128
    hidden_size: int = 64
    intermediate_size: int = 128
    num_hidden_layers: int = 2
    num_attention_heads: int = 2
    num_key_value_heads: int = 1
    head_dim: int = 32
    sliding_window: int = 4096
    query_pre_attn_scalar: int = 32
    hidden_activation: str = "gelu_pytorch_tanh"  # Gemma-2's; "gelu" as above


@dataclass
class ModelCfg:
    name: str = "tiny"
    # Local PaliGemma directory (config.json + safetensors); null builds the backbone from `vision`/`text`.
    pretrained_path: str | None = None
    # Local tokenizer directory; null builds the project's word-level tokenizer (tiny/small configs).
    tokenizer_path: str | None = None
    vision: VisionCfg = field(default_factory=VisionCfg)
    text: TextCfg = field(default_factory=TextCfg)
    attn_implementation: str | None = None  # transformers' choice when null (eager for Gemma-2)
    dit: str = "Ti"  # DiT size: CogACT's S, B or L, or Ti for CPU tests
    dit_gelu: str = "tanh"  # the DiT MLP's GELU: CogACT's "tanh" approximation or "none" (exact, CPU-fast)
    # dtype the pretrained backbone's weights load in: bfloat16 halves a 3B model's weights, gradients and
    # AdamW state on GPUs; the action head stays float32 and gets the cognition feature cast to it.
    dtype: str = "float32"
    prompt: str = "What action should the robot take to {instruction}?"


@dataclass
class InputsCfg:
    """Which observations the policy sees (the paper's ablation axes)."""

    cameras: list[str] = field(default_factory=lambda: list(CAMERAS))
    states: list[str] = field(default_factory=lambda: ["wrist_pose"])
    # Fraction of training samples whose state feature is withheld: the state then cannot stand in for what
    # only the cameras show (where the object is), so the image features must carry it.
    state_dropout: float = 0.0
    # Standard deviation (m, each axis) of an error on the grasp point input, as a detector's estimate of
    # where the object is would be off: one draw per training sample, one world-frame offset per episode
    # in evaluation. The state alone then brings the hand near the object, not onto it.
    grasp_point_noise: float = 0.0


@dataclass
class DiffusionCfg:
    chunk: int = 16
    train_timesteps: int = 100
    beta_schedule: str = "squaredcos_cap_v2"
    repeated_steps: int = 4  # CogACT's effective default: r noise draws per backbone pass
    cfg_dropout: float = 0.1  # 0 disables classifier-free guidance (no null embedding)
    cfg_scale: float = 1.5
    ddim_steps: int = 10


@dataclass
class DataCfg:
    root: str = "outputs/data/g1/lerobot"
    repo_id: str = "mobilemani/g1"
    episodes: list[int] | None = None  # null: every episode
    heldout_episodes: int = 4  # whole episodes kept out of training for the diagnostics (seeded choice)
    # decoded-frame cache next to the dataset (mobilemani_vla.data.frame_cache); false: decode per sample
    cache: bool = True
    video_backend: str = "pyav"
    num_workers: int = 0


@dataclass
class TrainCfg:
    """Defaults = the CPU recipe (conf/vla/train/cpu.yaml); conf/vla/train/paper.yaml is CogACT's setting."""

    batch_size: int = 32  # global batch, split over processes
    steps: int = 6000
    lr: float = 3e-4
    lr_schedule: str = "cosine"  # a diffusers.optimization schedule name: constant, cosine, linear, ...
    warmup_steps: int = 200
    # Steps at the start with the backbone's learning rate at zero, its rate then warmed up over warmup_steps:
    # the action head first learns to read the untrained backbone's features (linear probing before
    # fine-tuning), so that the head's random start does not push every frame's feature to one value.
    backbone_hold_steps: int = 0
    weight_decay: float = 0.01
    # State quantities the cognition feature is also trained to regress (a linear read-out, MSE in normalised
    # units, weighted by cognition_target_weight): e.g. [grasp_point], where the object is, which only the
    # cameras show. A backbone trained from scratch otherwise gets only the diffusion loss's weak gradient.
    cognition_targets: list[str] = field(default_factory=list)
    cognition_target_weight: float = 1.0
    ema_decay: float = (
        0.999  # > 0: an exponential moving average of the weights, saved and used for evaluation
    )
    grad_clip: float = 1.0
    mixed_precision: str = "no"  # "bf16" on GPUs
    gradient_checkpointing: bool = False
    # torch.compile the model being trained (inductor, which needs a C++ compiler at run time): faster steps
    # after a compile at the start of every run or piece (docs/results/throughput.md); the saved weights and
    # the averaged copy stay plain
    compile: bool = False
    log_every: int = 10
    diagnose_every: int = (
        500  # > 0: held-out diagnostics (noise error with image vs null feature, open-loop error)
    )
    diagnose_frames: int = 64  # held-out frames the diagnostics use (a fixed, evenly spaced choice)
    diagnose_cfg_scales: list[float] = field(default_factory=lambda: [1.0, 1.5])  # open-loop error per scale
    save_every: int = 500
    keep_checkpoints: int = 2
    # > 0: this run is one piece of a longer one: after this many minutes it saves a checkpoint and stops,
    # and the next run on train.output_dir resumes there (0: run to train.steps)
    piece_minutes: float = 0.0
    resume: bool = True  # continue from the newest checkpoint in output_dir; false: refuse one that holds any
    logger: str = "wandb"  # "wandb" (offline unless WANDB_MODE says otherwise) or "none"
    progress: bool = True
    seed: int = 0
    output_dir: str = "outputs/vla/g1/default/tiny"
    augment: AugmentCfg = field(default_factory=AugmentCfg)  # train-time image augmentation


@dataclass
class VLACfg:
    robot: str = "g1"
    name: str = "default"
    model: ModelCfg = field(default_factory=ModelCfg)
    inputs: InputsCfg = field(default_factory=InputsCfg)
    diffusion: DiffusionCfg = field(default_factory=DiffusionCfg)
    data: DataCfg = field(default_factory=DataCfg)
    train: TrainCfg = field(default_factory=TrainCfg)

    @property
    def action_dim(self) -> int:
        return ROBOT_ACTION_DIMS[self.robot]

    @property
    def read_states(self) -> list[str]:
        """The states training reads: the inputs, then the cognition feature's targets, each once."""
        return list(dict.fromkeys([*self.inputs.states, *self.train.cognition_targets]))

    def validate(self) -> VLACfg:
        """Stop with one message naming the key and the valid choices (before anything is written)."""
        # imported here: reading a config (evaluation, tables) need not load the training stack
        from accelerate.utils import PrecisionType
        from diffusers.optimization import SchedulerType

        t, d, data = self.train, self.diffusion, self.data
        vision, text = self.model.vision, self.model.text
        check_positive(
            {
                "train.steps": t.steps,
                "train.batch_size": t.batch_size,
                "train.log_every": t.log_every,
                "train.save_every": t.save_every,
                "train.keep_checkpoints": t.keep_checkpoints,
                "train.diagnose_frames": t.diagnose_frames,
                "diffusion.chunk": d.chunk,
                "diffusion.train_timesteps": d.train_timesteps,
                "diffusion.repeated_steps": d.repeated_steps,
                "diffusion.ddim_steps": d.ddim_steps,
            }
        )
        check_values(
            [
                ("train.lr", t.lr, t.lr > 0, "above 0"),
                ("train.piece_minutes", t.piece_minutes, t.piece_minutes >= 0, ">= 0; 0: no limit"),
                ("train.warmup_steps", t.warmup_steps, t.warmup_steps >= 0, ">= 0"),
                ("train.backbone_hold_steps", t.backbone_hold_steps, t.backbone_hold_steps >= 0, ">= 0"),
                ("train.ema_decay", t.ema_decay, 0 <= t.ema_decay < 1, "in [0, 1); 0 keeps no average"),
                ("train.grad_clip", t.grad_clip, t.grad_clip >= 0, ">= 0; 0 clips nothing"),
                (
                    "inputs.state_dropout",
                    self.inputs.state_dropout,
                    0 <= self.inputs.state_dropout < 1,
                    "in [0, 1)",
                ),
                (
                    "inputs.grasp_point_noise",
                    self.inputs.grasp_point_noise,
                    self.inputs.grasp_point_noise >= 0
                    and (self.inputs.grasp_point_noise == 0 or "grasp_point" in self.inputs.states),
                    ">= 0, and 0 unless inputs.states holds grasp_point",
                ),
                ("diffusion.cfg_dropout", d.cfg_dropout, 0 <= d.cfg_dropout < 1, "in [0, 1); 0: no guidance"),
                ("diffusion.ddim_steps", d.ddim_steps, d.ddim_steps <= d.train_timesteps, "<= its timesteps"),
                ("diffusion.cfg_scale", d.cfg_scale, d.cfg_scale >= 0, ">= 0; 1: no guidance"),
                (
                    "train.diagnose_cfg_scales",
                    t.diagnose_cfg_scales,
                    all(scale >= 0 for scale in t.diagnose_cfg_scales),
                    "guidance scales, each >= 0",
                ),
                (
                    "model.vision.num_attention_heads",
                    vision.num_attention_heads,
                    vision.num_attention_heads >= 1 and vision.hidden_size % vision.num_attention_heads == 0,
                    f"a divisor of model.vision.hidden_size={vision.hidden_size}",
                ),
                (
                    "model.text.num_key_value_heads",
                    text.num_key_value_heads,
                    text.num_key_value_heads >= 1
                    and text.num_attention_heads % text.num_key_value_heads == 0,
                    f"a divisor of model.text.num_attention_heads={text.num_attention_heads}",
                ),
                (
                    "train.cognition_target_weight",
                    t.cognition_target_weight,
                    t.cognition_target_weight >= 0,
                    ">= 0",
                ),
                ("data.heldout_episodes", data.heldout_episodes, data.heldout_episodes >= 0, ">= 0"),
                ("data.num_workers", data.num_workers, data.num_workers >= 0, ">= 0"),
            ]
        )
        _choices("train.mixed_precision", [t.mixed_precision], PrecisionType.list())
        _choices("train.lr_schedule", [t.lr_schedule], [schedule.value for schedule in SchedulerType])
        _choices("train.logger", [t.logger], ("wandb", "none"))
        _choices("diffusion.beta_schedule", [d.beta_schedule], BETA_SCHEDULES)
        _choices("data.video_backend", [data.video_backend], VIDEO_BACKENDS)
        _choices("robot", [self.robot], ROBOT_ACTION_DIMS)
        _choices("inputs.cameras", self.inputs.cameras, IMAGE_STREAMS)
        _choices("inputs.states", self.inputs.states, STATES)
        _choices("train.cognition_targets", t.cognition_targets, STATES)
        _choices("model.dit", [self.model.dit], DIT_PRESETS)
        _choices("model.dit_gelu", [self.model.dit_gelu], GELU_APPROXIMATIONS)
        _choices("model.dtype", [self.model.dtype], DTYPES)
        if not self.inputs.cameras:
            raise InputError(f"inputs.cameras must name at least one of {list(IMAGE_STREAMS)}")
        return self


def _choices(kind: str, values: list[str], valid) -> None:
    bad = [v for v in values if v not in valid]
    if bad or len(set(values)) != len(values):
        raise InputError(f"invalid {kind} {values}: each must be one of {list(valid)}, without repeats")


@dataclass
class VLARootCfg(VLACfg):
    """conf/vla.yaml's schema: VLACfg with the robot group's block, of which `robot` is a copy."""

    task: RobotChoiceCfg = field(default_factory=RobotChoiceCfg)


ROOT_ONLY = ("task",)  # VLARootCfg's keys that VLACfg leaves out
register_schema("vla_schema", VLARootCfg)


def compose_vla_cfg(overrides: list[str]) -> VLACfg:
    """conf/vla.yaml with command-line style overrides, as `python -m mobilemani_vla.train` would see it (for
    benchmarks and tests, which run outside Hydra's entry point)."""
    with initialize_config_dir(config_dir=str(CONF_DIR), version_base="1.3"):
        return to_dataclass(
            compose(config_name="vla", overrides=overrides), VLACfg, ignore=ROOT_ONLY
        ).validate()


def vla_cfg_from_yaml(text: str) -> VLACfg:
    return to_dataclass(OmegaConf.create(text), VLACfg).validate()


def vla_cfg_to_yaml(cfg: VLACfg) -> str:
    return OmegaConf.to_yaml(OmegaConf.structured(cfg))

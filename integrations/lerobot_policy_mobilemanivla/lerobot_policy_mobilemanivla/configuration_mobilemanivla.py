"""`--policy.type=mobilemanivla`: the config of MobileManiVLA as a LeRobot policy.

The network, its sizes and its training settings are the project's VLA config (conf/vla.yaml composed with
`--policy.preset`, a conf/vla/model option, and `--policy.overrides`, e.g. '[+experiment=demo]' or
'[diffusion.ddim_steps=5,inputs.state_dropout=0.3]'), recorded whole in `vla_yaml` once the policy is built,
so a checkpoint reloads without composing anything. LeRobot's pipelines leave every feature as it is
(IDENTITY): the model normalises actions and states itself with the dataset's global min/max bounds
(mobilemani_vla.model.normalizer), as our own training does.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from lerobot.configs import NormalizationMode, PreTrainedConfig
from lerobot.optim import AdamWConfig, DiffuserSchedulerConfig
from lerobot.utils.constants import ACTION

from mobilemani_rl.utils.config_store import group_options
from mobilemani_rl.utils.errors import InputError, check_choice
from mobilemani_vla.config import (
    IMAGE_STREAMS,
    ROBOT_ACTION_DIMS,
    VLACfg,
    compose_vla_cfg,
    vla_cfg_from_yaml,
    vla_cfg_to_yaml,
)
from mobilemani_vla.model.ensemble import EnsembleCfg
from mobilemani_vla.model.processor import STATE_SOURCES, camera_key


@PreTrainedConfig.register_subclass("mobilemanivla")
@dataclass
class MobileManiVLAConfig(PreTrainedConfig):
    preset: str | None = None  # conf/vla/model/<preset>.yaml; None: conf/vla.yaml's (or an experiment's)
    overrides: list[str] = field(default_factory=list)  # more conf/vla.yaml overrides
    # VLA camera names (head_rgb, head_depth, wrist_rgb, wrist_depth); None: those of the VLA config's
    # inputs.cameras the dataset has
    cameras: list[str] | None = None
    # The training dataset's instructions: the word-level tokenizer's vocabulary (filled in by training)
    tasks: list[str] = field(default_factory=list)
    ensemble: EnsembleCfg = field(default_factory=EnsembleCfg)  # chunks -> one action per step
    vla_yaml: str | None = None  # the resolved VLA config (filled in when the policy is built)
    normalization_mapping: dict[str, NormalizationMode] = field(
        default_factory=lambda: {
            "VISUAL": NormalizationMode.IDENTITY,
            "STATE": NormalizationMode.IDENTITY,
            "ACTION": NormalizationMode.IDENTITY,
        }
    )

    def vla_cfg(self) -> VLACfg:
        """The recorded VLA config, else conf/vla.yaml with `preset` and `overrides`."""
        if self.vla_yaml is not None:
            return vla_cfg_from_yaml(self.vla_yaml)
        if self.preset is None:
            return compose_vla_cfg(self.overrides)
        check_choice(self.preset, group_options("vla/model"), "policy.preset")
        return compose_vla_cfg([f"vla/model={self.preset}", *self.overrides])

    def record(self, cfg: VLACfg) -> None:
        self.vla_yaml = vla_cfg_to_yaml(cfg)

    def get_optimizer_preset(self) -> AdamWConfig:
        train = self.vla_cfg().train
        return AdamWConfig(lr=train.lr, weight_decay=train.weight_decay, grad_clip_norm=train.grad_clip)

    def get_scheduler_preset(self) -> DiffuserSchedulerConfig:
        train = self.vla_cfg().train
        return DiffuserSchedulerConfig(name=train.lr_schedule, num_warmup_steps=train.warmup_steps)

    def validate_features(self) -> None:
        """The robot (from the action's width) and the cameras and states against the dataset's features,
        recorded in the VLA config; called when the policy is built, once the features are known."""
        cfg = self.vla_cfg()
        action = (self.output_features or {}).get(ACTION)
        robots = {dim: robot for robot, dim in ROBOT_ACTION_DIMS.items()}
        if action is None or action.shape[0] not in robots:
            raise InputError(
                f"MobileManiVLA predicts an {ACTION!r} of width {sorted(robots)} "
                f"(robots {sorted(ROBOT_ACTION_DIMS)}); "
                f"the output features are {self.output_features}"
            )
        inputs = self.input_features or {}
        available = [c for c in IMAGE_STREAMS if camera_key(c) in inputs]
        wanted = cfg.inputs.cameras if self.cameras is None else self.cameras
        cameras = [c for c in wanted if c in available] if self.cameras is None else list(wanted)
        if not cameras or any(c not in available for c in cameras):
            raise InputError(f"policy.cameras={wanted}: the dataset has the VLA cameras {available}")
        unread = [s for s in cfg.inputs.states if STATE_SOURCES[s][0] not in inputs]
        if unread:
            raise InputError(
                f"inputs.states {unread} read features LeRobot does not give a policy (it gives "
                f"{sorted(inputs)}); leave them out of policy.overrides"
            )
        self.cameras = cameras
        inputs_cfg = replace(cfg.inputs, cameras=cameras)
        self.record(replace(cfg, robot=robots[action.shape[0]], inputs=inputs_cfg).validate())

    @property
    def observation_delta_indices(self) -> None:
        return None  # one observation step

    @property
    def action_delta_indices(self) -> list[int]:
        return list(range(self.vla_cfg().diffusion.chunk))

    @property
    def reward_delta_indices(self) -> None:
        return None

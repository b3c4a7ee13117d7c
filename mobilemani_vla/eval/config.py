"""Closed-loop evaluation config: EvalRootCfg is conf/eval.yaml's schema, its groups
conf/eval/{protocol,split,policy} change the defaults of `subset` and `policy`. A composed config converts
with `to_dataclass(with_env_task(cfg), EvalCfg).check()`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import get_args

from hydra import compose, initialize_config_dir

from mobilemani_rl.envs.base_frame import Convention
from mobilemani_rl.envs.config import EnvCfg, EnvParamsCfg, RobotChoiceCfg, check_env_block, with_env_task
from mobilemani_rl.envs.tasks import SubsetCfg
from mobilemani_rl.utils.config_store import CONF_DIR, register_schema, to_dataclass
from mobilemani_rl.utils.errors import check_choice, check_positive, check_torch_device, check_values
from mobilemani_vla.model.ensemble import EnsembleCfg


@dataclass
class PolicyCfg:
    kind: str = "vla"  # vla | lerobot | teacher | scripted | random
    checkpoint: str | None = None  # vla: checkpoint dir; lerobot: pretrained_model dir; teacher: model_*.pt
    runs_dir: str = (
        "outputs/rl"  # teacher without a checkpoint: newest <runs_dir>/<robot>/<object or category>/<skill>
    )
    device: str = "cpu"
    batch_size: int = 16  # model policies: envs per forward pass
    rename: dict[str, str] = field(default_factory=dict)  # lerobot: our feature name -> the policy's
    # vla: every prediction with the learned null vector in place of the image feature and without guidance,
    # as the diagnostics' null image: what the closed loop loses without the cameras
    null_image: bool = False


DEFAULT_IMAGE_SIZE = (224, 224)


@dataclass
class EvalCfg:
    robot: str = "g1"
    name: str = "default"  # run name: results go to <output_dir>/<robot>/<name>/<split>.jsonl
    output_dir: str = "outputs/eval"
    policy: PolicyCfg = field(default_factory=PolicyCfg)
    subset: SubsetCfg = field(default_factory=lambda: SubsetCfg(split="test"))  # `episodes` per combination
    episodes_per_batch: int = (
        10  # episodes run together (at most subset.episodes); seeds are per block of this size
    )
    seed: int = 0  # a block's env seed mixes (robot, object, skill, scene) and its first episode, seed + e
    ensemble: EnsembleCfg = field(default_factory=EnsembleCfg)
    action_convention: str = (
        "conjugate"  # base-frame action encoding of the training data (base_frame.Convention)
    )
    # Rendered (height, width); null: the size the policy's training images had (VLA checkpoints record it),
    # else DEFAULT_IMAGE_SIZE.
    image_size: list[int] | None = None
    video_episodes: int = 0  # head-camera MP4s of the first k episodes of each combination
    # Processes running blocks side by side (mobilemani_rl.utils.process_pool), each with its own policy and
    # an equal share of the CPU's threads; results do not depend on it, so a rerun may change it.
    workers: int = 1
    # Minutes after which no further block starts (0: no limit): the run stops with its results file
    # resumable and without a summary, so it does not look complete; the same command runs the rest.
    piece_minutes: float = 0.0
    env: EnvCfg = field(default_factory=EnvCfg)

    @property
    def batch_size(self) -> int:
        """Episodes per env batch. Clipped to a combination's episodes because a protocol preset
        (conf/eval/protocol, `@package subset`) cannot set the root's episodes_per_batch:
        `small`'s 2 episodes run as one batch of 2."""
        return min(self.episodes_per_batch, self.subset.episodes)

    @property
    def split_name(self) -> str:
        """'<object split>_objects_<scene split>_scenes', e.g. the paper's protocol:
        test_objects_test_scenes."""
        return f"{self.subset.split}_objects_{self.subset.scene_split or self.subset.split}_scenes"

    def check(self) -> EvalCfg:
        check_positive(
            {
                "subset.episodes": self.subset.episodes,
                "episodes_per_batch": self.episodes_per_batch,
                "workers": self.workers,
                "subset.scenes_per_object": self.subset.scenes_per_object,
                "subset.objects_per_category": self.subset.objects_per_category,
                "policy.batch_size": self.policy.batch_size,
                "ensemble.horizon": self.ensemble.horizon,
            }
        )
        videos, index, size = self.video_episodes, self.ensemble.action_index, self.image_size
        check_values(
            [
                ("video_episodes", videos, videos >= 0, "episodes to record, >= 0"),
                (
                    "ensemble.action_index",
                    index,
                    index >= -1,
                    "-1: adaptive ensemble, else a chunk index",
                ),
                ("image_size", size, size is None or (len(size) == 2 and min(size) >= 1), "[height, width]"),
                ("piece_minutes", self.piece_minutes, self.piece_minutes >= 0, ">= 0; 0: no limit"),
            ]
        )
        check_choice(self.action_convention, get_args(Convention), "action_convention")
        check_torch_device(self.policy.device, "policy.device")
        check_env_block(self.env, {"num_envs": "episodes_per_batch", "seed": "seed"})
        return self


@dataclass
class EvalRootCfg(EvalCfg):
    """conf/eval.yaml's schema: the env block without its task, which the robot group's block makes."""

    env: EnvParamsCfg = field(default_factory=EnvParamsCfg)
    task: RobotChoiceCfg = field(default_factory=RobotChoiceCfg)


register_schema("eval_schema", EvalRootCfg)


def compose_eval_cfg(overrides: list[str]) -> EvalCfg:
    """conf/eval.yaml with command-line style overrides, checked, as `python -m mobilemani_vla.eval.evaluate`
    would see it (for commands that run evaluations in their own process, and tests)."""
    with initialize_config_dir(config_dir=str(CONF_DIR), version_base="1.3"):
        cfg = compose(config_name="eval", overrides=overrides)
    return to_dataclass(with_env_task(cfg), EvalCfg).check()

"""The RL entry points' configs: PPO settings (conf/rl/ppo presets change PpoCfg's defaults), their
translation into rsl-rl-lib 5's config dict, and the schemas of the roots conf/rl.yaml and
conf/eval_rl.yaml."""

from __future__ import annotations

import copy
import os
from dataclasses import dataclass, field, fields

from mobilemani_rl.envs.config import EnvCfg, EnvParamsCfg, TaskCfg, check_env_block
from mobilemani_rl.utils.config_store import register_schema
from mobilemani_rl.utils.errors import (
    SEED_RULE,
    InputError,
    UnknownNameError,
    check_choice,
    check_positive,
    check_torch_device,
    check_values,
    is_seed,
)

LOGGERS = ("tensorboard", "wandb")
SCHEDULES = ("adaptive", "fixed")  # rsl-rl's PPO learning-rate schedules
PRECISIONS = ("fp32", "bf16", "auto")  # of the PPO update's forward passes


@dataclass
class WarmStartCfg:
    """Behaviour cloning of the scripted policy before PPO (mobilemani_rl.rl.warm_start);
    off in the reference."""

    episodes: int = (
        0  # scripted episodes per object (rounded up to whole batches); 0: from scratch (reference)
    )
    action_noise: float = (
        0.3  # std of the noise on the executed scripted actions, not their labels (0.5 clones worse)
    )
    epochs: int = 20
    mini_batch_size: int = 1024
    learning_rate: float = 1e-3
    noise_std: float = 0.3  # action noise PPO starts from: the cloned actions need refinement, not a search
    seed: int = 100_000  # first seed of the scripted episodes (evaluation uses 1000 upward)


@dataclass
class PpoCfg:
    """Defaults are the reference's (docs/reference.md, "PPO"); conf/rl/ppo/paper.yaml changes none."""

    num_envs: int = 1024
    num_steps_per_env: int = 16
    max_iterations: int = 4000
    save_interval: int = 100  # reference: 4000 (end only); more often here so an interrupted run resumes
    learning_rate: float = 1e-3
    schedule: str = "adaptive"
    desired_kl: float = 0.008
    num_learning_epochs: int = 8
    num_mini_batches: int = 8
    gamma: float = 0.99
    lam: float = 0.95
    clip_param: float = 0.2
    value_loss_coef: float = 1.0
    use_clipped_value_loss: bool = True
    entropy_coef: float = 0.0
    max_grad_norm: float = 1.0
    normalize_advantage_per_mini_batch: bool = False
    actor_hidden_dims: list[int] = field(default_factory=lambda: [1024, 1024, 512, 512])
    critic_hidden_dims: list[int] = field(default_factory=lambda: [1024, 1024, 512, 512])
    activation: str = "elu"
    init_noise_std: float = 1.0
    # Bounds on the action noise std (rsl-rl clamps it): keeps an entropy bonus from growing it without limit.
    noise_std_range: tuple[float, float] = (1e-6, 1e6)  # reference: unbounded
    obs_normalization: bool = True  # reference: empirical_normalization
    init_at_random_ep_len: bool = True
    seed: int = 42
    torch_threads: int = 0  # threads while collecting (policy inference beside MuJoCo); 0: torch's default
    # threads for the network updates (PPO epochs, warm-start fitting), MuJoCo idle; 0: torch's default
    update_threads: int = 0
    # PPO's forward passes, in the update and in collection: bf16 autocast (rsl-rl's use_mixed_precision,
    # output layers kept in fp32), fp32 (reference), or auto: bf16 where the CPU multiplies bf16 natively
    # (AVX512-BF16 or AMX), else fp32
    precision: str = "fp32"
    # where PPO's networks run: cpu, cuda or cuda:<index>; MuJoCo and the env's numpy stay on the CPU
    device: str = "cpu"
    warm_start: WarmStartCfg = field(default_factory=WarmStartCfg)


@dataclass
class RlGroupCfg:
    ppo: PpoCfg = field(default_factory=PpoCfg)


@dataclass
class RLCfg:
    """conf/rl.yaml's schema: a training run (python -m mobilemani_rl.rl.train), also its saved
    config.yaml."""

    task: TaskCfg = field(default_factory=TaskCfg)
    env: EnvParamsCfg = field(default_factory=EnvParamsCfg)
    rl: RlGroupCfg = field(default_factory=RlGroupCfg)
    # task.object may name a category (e.g. laptop): one policy over up to this many of its train objects.
    objects_per_policy: int = 8
    # One directory per task, so that rerunning the same command resumes it.
    run_dir: str = "outputs/rl/${task.robot}/${task.object}/${task.skill}"
    eval_episodes: int = 0  # > 0: evaluate the final checkpoint on this many seeded episodes
    logger: str = "tensorboard"  # tensorboard | wandb (offline unless WANDB_MODE says otherwise)
    wandb_project: str = "mobilemanibench"

    def check(self) -> RLCfg:
        """Every value checked before a run directory is written, each error naming its key."""
        # imported here: the schema module stays light (no torch, no object catalogue) for config tools
        from rsl_rl.utils import resolve_nn_activation

        from mobilemani_rl.assets.objects import CATEGORIES, OBJECTS, catalog_ids, check_skill, object_choices
        from mobilemani_rl.assets.robots import get_robot
        from mobilemani_rl.assets.scenes.placements import check_setting, get_placement

        ppo = self.rl.ppo
        check_positive(
            {
                "rl.ppo.num_envs": ppo.num_envs,
                "rl.ppo.num_steps_per_env": ppo.num_steps_per_env,
                "rl.ppo.max_iterations": ppo.max_iterations,
                "rl.ppo.save_interval": ppo.save_interval,
                "rl.ppo.num_learning_epochs": ppo.num_learning_epochs,
                "rl.ppo.num_mini_batches": ppo.num_mini_batches,
                "objects_per_policy": self.objects_per_policy,
                "rl.ppo.warm_start.epochs": ppo.warm_start.epochs,
                "rl.ppo.warm_start.mini_batch_size": ppo.warm_start.mini_batch_size,
            }
        )
        if self.eval_episodes < 0:
            raise InputError(f"eval_episodes={self.eval_episodes} must be 0 (no evaluation) or more")
        samples, warm = ppo.num_envs * ppo.num_steps_per_env, ppo.warm_start
        hidden = [*ppo.actor_hidden_dims, *ppo.critic_hidden_dims]
        check_values(
            [
                ("rl.ppo.learning_rate", ppo.learning_rate, ppo.learning_rate > 0, "above 0"),
                ("rl.ppo.gamma", ppo.gamma, 0 < ppo.gamma <= 1, "a discount, in (0, 1]"),
                ("rl.ppo.lam", ppo.lam, 0 <= ppo.lam <= 1, "GAE's lambda, in [0, 1]"),
                ("rl.ppo.clip_param", ppo.clip_param, ppo.clip_param > 0, "above 0"),
                ("rl.ppo.desired_kl", ppo.desired_kl, ppo.desired_kl > 0, "above 0"),
                ("rl.ppo.init_noise_std", ppo.init_noise_std, ppo.init_noise_std > 0, "above 0"),
                ("rl.ppo.entropy_coef", ppo.entropy_coef, ppo.entropy_coef >= 0, ">= 0"),
                ("rl.ppo.max_grad_norm", ppo.max_grad_norm, ppo.max_grad_norm > 0, "above 0"),
                (
                    "rl.ppo.num_mini_batches",
                    ppo.num_mini_batches,
                    ppo.num_mini_batches <= samples,
                    f"at most the {samples} samples of an iteration (num_envs x num_steps_per_env)",
                ),
                (
                    "rl.ppo.actor/critic_hidden_dims",
                    hidden,
                    bool(hidden) and min(hidden) >= 1,
                    "layer widths >= 1",
                ),
                (
                    "rl.ppo.torch_threads",
                    ppo.torch_threads,
                    ppo.torch_threads >= 0,
                    ">= 0; 0: torch's default",
                ),
                (
                    "rl.ppo.update_threads",
                    ppo.update_threads,
                    ppo.update_threads >= 0,
                    ">= 0; 0: torch's default",
                ),
                ("rl.ppo.warm_start.episodes", warm.episodes, warm.episodes >= 0, ">= 0; 0: no warm start"),
                ("rl.ppo.seed", ppo.seed, is_seed(ppo.seed), SEED_RULE),
                ("rl.ppo.warm_start.seed", warm.seed, is_seed(warm.seed), SEED_RULE),
                ("rl.ppo.warm_start.action_noise", warm.action_noise, warm.action_noise >= 0, ">= 0"),
                ("rl.ppo.warm_start.learning_rate", warm.learning_rate, warm.learning_rate > 0, "above 0"),
                ("rl.ppo.warm_start.noise_std", warm.noise_std, warm.noise_std > 0, "above 0"),
            ]
        )
        check_choice(self.logger, LOGGERS, "logger")
        check_choice(ppo.schedule, SCHEDULES, "rl.ppo.schedule")
        check_choice(ppo.precision, PRECISIONS, "rl.ppo.precision")
        check_torch_device(ppo.device, "rl.ppo.device")
        try:
            resolve_nn_activation(ppo.activation)
        except ValueError as err:
            raise InputError(f"rl.ppo.activation: {err}") from err
        get_robot(self.task.robot)
        if self.task.object in CATEGORIES:  # its objects are of one kind: the first has the category's skills
            obj = OBJECTS[catalog_ids(self.task.object)[0]]
        elif self.task.object in OBJECTS:
            obj = OBJECTS[self.task.object]
        else:
            raise UnknownNameError(
                f"unknown task.object {self.task.object!r}; valid: an object ({object_choices()}) "
                f"or a category, which trains one policy for several of its objects ({', '.join(CATEGORIES)})"
            )
        check_skill(obj, self.task.skill)
        if self.task.scene:
            check_setting(obj, get_placement(self.task.scene))
        check_env_block(self.env, {"num_envs": "rl.ppo.num_envs", "seed": "rl.ppo.seed"})
        return self

    def env_cfg(self) -> EnvCfg:
        """The env block with the task: a copy, free to change."""
        params = {f.name: getattr(self.env, f.name) for f in fields(EnvParamsCfg)}
        return copy.deepcopy(EnvCfg(**params, task=self.task))


@dataclass
class EvalRlCfg:
    """conf/eval_rl.yaml's schema (python -m mobilemani_rl.rl.eval)."""

    checkpoint: str | None = None  # a model_*.pt of a training run
    episodes: int = 256  # per evaluated object; the paper evaluates 1024
    seed: int = 1000  # evaluation seeds differ from training's
    video_episodes: int = 0  # head-camera MP4s of the first k episodes

    def check(self) -> EvalRlCfg:
        if self.checkpoint is None:
            raise InputError("checkpoint=<path to a model_*.pt> is required")
        check_positive({"episodes": self.episodes})
        if self.video_episodes < 0:
            raise InputError(f"video_episodes={self.video_episodes} must be 0 (no videos) or more")
        if not is_seed(self.seed):
            raise InputError(f"seed={self.seed} must be {SEED_RULE}")
        return self


register_schema("rl_schema", RLCfg)
register_schema("eval_rl_schema", EvalRlCfg)


def cpu_multiplies_bf16_natively() -> bool:
    """The CPU has bf16 dot products (AVX512-BF16 or AMX) and torch may use them: ATen dispatches to its
    AVX-512 kernels and oneDNN is not held below its bf16 ISAs. Held to AVX2 (ATEN_CPU_CAPABILITY=avx2,
    ONEDNN_MAX_CPU_ISA=AVX2, as on a CPU without AVX-512) bf16 runs emulated, ~10x slower than fp32
    (docs/results/throughput.md)."""
    import torch

    hardware = torch.cpu._is_avx512_bf16_supported() or torch.cpu._is_amx_tile_supported()
    onednn_isa = os.environ.get("ONEDNN_MAX_CPU_ISA", "ALL").upper()
    onednn_bf16 = onednn_isa == "ALL" or any(k in onednn_isa for k in ("BF16", "AMX", "FP16", "AVX10"))
    return hardware and onednn_bf16 and torch.backends.cpu.get_cpu_capability() == "AVX512"


def update_precision(ppo: PpoCfg) -> str:
    """fp32 or bf16: `auto` picks bf16 only where it is fast (emulated bf16 is slower than fp32)."""
    if ppo.precision != "auto":
        return ppo.precision
    if ppo.device.startswith("cuda"):
        import torch

        native = torch.cuda.is_bf16_supported(including_emulation=False)
    else:
        native = cpu_multiplies_bf16_natively()
    return "bf16" if native else "fp32"


def rsl_rl_train_cfg(ppo: PpoCfg, logger: dict | str, run_name: str) -> dict:
    """The `train_cfg` dict OnPolicyRunner expects (rsl-rl-lib 5.x: separate actor and critic models)."""

    def model(hidden: list[int], distribution: bool) -> dict:
        cfg = {
            "class_name": "MLPModel",
            "hidden_dims": list(hidden),
            "activation": ppo.activation,
            "obs_normalization": ppo.obs_normalization,
        }
        if distribution:
            cfg["distribution_cfg"] = {
                "class_name": "GaussianDistribution",
                "init_std": ppo.init_noise_std,
                "std_range": tuple(ppo.noise_std_range),
                "std_type": "scalar",
            }
        return cfg

    return {
        "num_steps_per_env": ppo.num_steps_per_env,
        "save_interval": ppo.save_interval,
        "obs_groups": {
            "actor": ["policy"],
            "critic": ["policy"],
        },  # no asymmetric critic, as in the reference
        "algorithm": {
            "class_name": "PPO",
            "learning_rate": ppo.learning_rate,
            "schedule": ppo.schedule,
            "desired_kl": ppo.desired_kl,
            "num_learning_epochs": ppo.num_learning_epochs,
            "num_mini_batches": ppo.num_mini_batches,
            "gamma": ppo.gamma,
            "lam": ppo.lam,
            "clip_param": ppo.clip_param,
            "value_loss_coef": ppo.value_loss_coef,
            "use_clipped_value_loss": ppo.use_clipped_value_loss,
            "entropy_coef": ppo.entropy_coef,
            "max_grad_norm": ppo.max_grad_norm,
            "normalize_advantage_per_mini_batch": ppo.normalize_advantage_per_mini_batch,
            "use_mixed_precision": update_precision(ppo) == "bf16",
        },
        "actor": model(ppo.actor_hidden_dims, distribution=True),
        "critic": model(ppo.critic_hidden_dims, distribution=False),
        "logger": logger,
        "run_name": run_name,
    }

"""rsl-rl's OnPolicyRunner with atomic checkpoints and a one-line progress bar instead of the console
block."""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F
from rsl_rl.runners import OnPolicyRunner
from rsl_rl.utils.logger import Logger
from tqdm import tqdm

from mobilemani_rl.rl.run_dir import CURVE
from mobilemani_rl.utils.errors import InputError, first_sentence
from mobilemani_rl.utils.io import read_json, write_json_atomic

SUCCESS_KEY = "/episode/success_flag"


@contextlib.contextmanager
def torch_threads(threads: int) -> Iterator[None]:
    """Run the block with `threads` torch threads (0: leave as is), then restore the previous count."""
    previous = torch.get_num_threads()
    if threads:
        torch.set_num_threads(threads)
    try:
        yield
    finally:
        torch.set_num_threads(previous)


def keep_output_layer_fp32(model: torch.nn.Module) -> None:
    """Run a model's last linear layer in fp32 inside a bf16 autocast: bf16 keeps ~3 significant digits,
    too few for values of a few hundred and for the log-probability ratios PPO clips at 0.2; the hidden
    layers, which hold nearly all the FLOPs, stay in bf16. The parameters are unchanged, so checkpoints
    are too."""
    layer = [m for m in model.modules() if isinstance(m, torch.nn.Linear)][-1]

    def forward(x: torch.Tensor) -> torch.Tensor:
        with torch.autocast(x.device.type, enabled=False):
            return F.linear(x.float(), layer.weight, layer.bias)

    layer.forward = forward


# Activations whose gradient can be computed from their output alone: they may overwrite their input.
OUTPUT_DIFFERENTIABLE = (torch.nn.ELU, torch.nn.CELU, torch.nn.SELU, torch.nn.ReLU, torch.nn.LeakyReLU)


def activations_in_place(model: torch.nn.Module) -> None:
    """Apply the hidden activations in place on the linear layers' outputs, which no backward needs: a pass
    without an allocation, and ELU's backward then reads its output instead of recomputing exp of its input
    (docs/results/throughput.md). Exact in fp32; in bf16 the gradient moves by less than bf16's own rounding
    moves it from fp32's. Autograd refuses any in-place write a backward would need."""
    for module in model.modules():
        if isinstance(module, OUTPUT_DIFFERENTIABLE):
            module.inplace = True


def with_fused_step(optimizer: torch.optim.Optimizer) -> torch.optim.Optimizer:
    """The same optimizer and settings with its fused step: one kernel over all parameters instead of several
    per tensor (a faster update, docs/results/throughput.md); the arithmetic is the same up to rounding, and
    checkpoints keep their format."""
    params = [p for group in optimizer.param_groups for p in group["params"]]
    return type(optimizer)(params, **{**optimizer.defaults, "fused": True})


class ProgressLogger(Logger):
    """Writes every metric as rsl-rl does (TensorBoard / W&B) but shows a tqdm bar with the success rate.

    It also keeps the per-iteration training curve (samples, success, reward) for plots.
    """

    def __init__(self, *args, total_iterations: int, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.total_iterations = total_iterations
        self.bar: tqdm | None = None
        self.curve: list[dict[str, float]] = []

    def log(self, it: int, *args, **kwargs) -> None:
        if self.bar is None:
            self.bar = tqdm(
                total=self.total_iterations, initial=it, desc="PPO", unit="it", dynamic_ncols=True
            )
        success = _episode_mean(self.ep_extras, SUCCESS_KEY)
        with contextlib.redirect_stdout(io.StringIO()):  # rsl-rl prints a 30-line block per iteration
            super().log(it, *args, **kwargs)
        reward = float(np.mean(self.rewbuffer)) if self.rewbuffer else float("nan")
        self.curve.append(
            {
                "iteration": it,
                "samples": self.tot_timesteps,
                "seconds": self.tot_time,
                "success": success,
                "reward": reward,
            }
        )
        self.bar.n = it + 1
        self.bar.set_postfix(
            success=_shown(success, ".2f"),
            reward=_shown(reward, ".1f"),
            sps=f"{self.tot_timesteps / max(self.tot_time, 1e-9):.0f}",
        )
        self.bar.refresh()


def _shown(value: float, spec: str) -> str:
    """'-' until an episode has ended (the curve keeps nan): "nan" on the bar reads like a diverged run."""
    return "-" if np.isnan(value) else format(value, spec)


def _episode_mean(extras: list[dict], key: str) -> float:
    values = [torch.as_tensor(e[key]).flatten() for e in extras if key in e]
    return float(torch.cat(values).float().mean()) if values else float("nan")


class MobileManiRunner(OnPolicyRunner):
    def __init__(
        self,
        env,
        train_cfg: dict,
        log_dir: str | None,
        total_iterations: int,
        update_threads: int = 0,
        device: str = "cpu",
    ) -> None:
        with contextlib.redirect_stdout(io.StringIO()):  # model summaries
            super().__init__(env, train_cfg, log_dir=log_dir, device=device)
        self.alg.optimizer = with_fused_step(self.alg.optimizer)
        activations_in_place(self.alg.actor)
        activations_in_place(self.alg.critic)
        # collection keeps few torch threads so MuJoCo has the cores; the update has them to itself
        self.alg.update = torch_threads(update_threads)(self.alg.update)  # a contextmanager decorates
        if self.alg.use_mixed_precision:
            keep_output_layer_fp32(self.alg.actor)
            keep_output_layer_fp32(self.alg.critic)
            # collection's forward passes (actions, values, the last value GAE bootstraps from) in the
            # update's precision: the update recomputes the same log-probabilities (PPO's ratio starts at 1),
            # and inference is faster
            for name in ("act", "compute_returns"):
                bf16 = torch.autocast(torch.device(device).type, dtype=torch.bfloat16)
                setattr(self.alg, name, bf16(getattr(self.alg, name)))
        self.logger = ProgressLogger(
            log_dir=log_dir,
            cfg=self.cfg,
            env_cfg=env.cfg,
            num_envs=env.num_envs,
            is_distributed=False,
            gpu_world_size=1,
            gpu_global_rank=0,
            device=device,
            total_iterations=total_iterations,
        )
        self.curve_path = Path(log_dir) / CURVE if log_dir else None

    def load(
        self, path: str, load_cfg: dict | None = None, strict: bool = True, map_location: str | None = None
    ) -> dict:
        """rsl-rl's load with `weights_only=True` (rsl-rl itself unpickles anything, so a crafted checkpoint
        would run code); a file that is not a readable checkpoint stops with its path. Tensors land on the
        runner's device, whichever device saved them."""
        try:
            loaded = torch.load(path, weights_only=True, map_location=map_location or self.device)
        except Exception as err:  # pickle, zip or safety errors all mean: not a checkpoint we can trust
            raise InputError(
                f"cannot load teacher checkpoint {path}: {type(err).__name__}: {first_sentence(err)}"
            ) from err
        if self.alg.load(loaded, load_cfg, strict):
            self.current_learning_iteration = loaded["iter"]
        return loaded["infos"]

    def resume_curve(self, start: int) -> None:
        """Continue the saved curve of a run resumed at iteration `start` (its rows from before the
        checkpoint); its sample and training-second counts go on from the last kept row, so they count the
        whole run, not the piece since the resume."""
        if self.curve_path is not None and self.curve_path.is_file():
            rows = read_json(self.curve_path)
            self.logger.curve = [row for row in rows if row["iteration"] < start]
            if self.logger.curve:
                self.logger.tot_timesteps = int(self.logger.curve[-1]["samples"])
                self.logger.tot_time = float(self.logger.curve[-1]["seconds"])

    def save(self, path: str, infos: dict | None = None) -> None:
        """Write to a temporary file, then rename: a killed run never leaves a truncated checkpoint. The curve
        up to the checkpoint is saved first, so a run resumed after a kill keeps its whole curve (a kill
        between the two leaves rows past the newest checkpoint, which the resume drops)."""
        if self.curve_path is not None:
            write_json_atomic(self.curve_path, self.logger.curve)
        tmp = f"{path}.tmp"
        super().save(tmp, infos)
        os.replace(tmp, path)

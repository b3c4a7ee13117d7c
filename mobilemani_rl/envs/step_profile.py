"""Where one batched step's time goes: `MobileManiEnv.step` through the rsl-rl adapter, split into its stages
by wall-clock timers around the env's own stage methods (no profiler hooks, which would tax Python-heavy
stages more than the physics).

Stages (each its exclusive time): the rsl-rl adapter (tensor conversions around the env step), actions + IK
(`apply_action`), physics (the substeps), frames (bulk reads from MuJoCo: poses, velocities, contacts),
observations, resets (less the frames they read), and the rest of the step (task distances, rewards,
terminations, logs).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import torch

from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.vecenv import RslRlVecEnv

STAGES = ("adapter", "actions_ik", "physics", "frames", "observations", "resets", "rest")


class StageTimer:
    """Exclusive wall time per stage: a timed call inside another counts in its own stage only."""

    def __init__(self, stages: tuple[str, ...] = STAGES) -> None:
        self.totals = dict.fromkeys(stages, 0.0)
        self._nested = [0.0]  # per open call: the time of the timed calls inside it

    def wrap(self, fn: Callable, stage: str) -> Callable:
        def timed(*args, **kwargs):
            self._nested.append(0.0)
            start = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                elapsed = time.perf_counter() - start
                self.totals[stage] += elapsed - self._nested.pop()
                self._nested[-1] += elapsed

        return timed


def profile_step(env: MobileManiEnv, steps: int, seed: int = 0) -> dict[str, float]:
    """Each stage's share of `steps` rsl-rl adapter steps of random actions (after one untimed step), and the
    adapter's env steps per second over them."""
    timer = StageTimer()
    physics = "_simulate_locked_base" if env.cfg.fixed_base else "_simulate"
    # Instance attributes shadow the methods `step` looks up on `self`.
    env.apply_action = timer.wrap(env.apply_action, "actions_ik")
    setattr(env, physics, timer.wrap(getattr(env, physics), "physics"))
    env.frame_reader.read = timer.wrap(env.frame_reader.read, "frames")
    env._observe = timer.wrap(env._observe, "observations")
    env._reset_envs = timer.wrap(env._reset_envs, "resets")
    env.step = timer.wrap(env.step, "rest")
    adapter = RslRlVecEnv(env)
    step = timer.wrap(adapter.step, "adapter")
    generator = torch.Generator().manual_seed(seed)
    actions = [torch.rand(env.num_envs, env.num_actions, generator=generator) * 2 - 1 for _ in range(64)]
    step(actions[0])
    timer.totals = dict.fromkeys(STAGES, 0.0)
    for k in range(steps):
        step(actions[k % len(actions)])
    total = sum(timer.totals.values())
    shares = {stage: round(timer.totals[stage] / total, 3) for stage in STAGES}
    return {**shares, "adapter_steps_per_s": round(steps * env.num_envs / total)}


def profile_table(rows: list[dict]) -> str:
    """Markdown: one row per (robot, envs) with each stage's share of the step."""
    head = "| robot | envs | steps/s | " + " | ".join(STAGES) + " |"
    lines = [head, "|" + "---|" * (3 + len(STAGES))]
    for r in rows:
        shares = " | ".join(f"{100 * r['profile'][s]:.1f}%" for s in STAGES)
        lines.append(f"| {r['robot']} | {r['num_envs']} | {r['profile']['adapter_steps_per_s']} | {shares} |")
    return "\n".join(lines)

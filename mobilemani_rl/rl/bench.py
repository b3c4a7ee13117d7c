"""PPO training throughput (samples/s including policy updates) for the cpu and paper presets, both robots,
against the raw physics limit of the same model and env count measured in the same run.

    python -m mobilemani_rl.rl.bench [--presets cpu paper] [--robots g1 xhand] [--iterations 3]
                                     [--variants "rl.ppo.precision=fp32" "rl.ppo.precision=bf16"]

--variants measures each preset once per variant, a space-separated list of Hydra overrides on top of the
preset (default, or `-`: the preset alone), in the same run: before and after a change on the same machine
load.

Each result also gives the shares of the timed iterations spent in PPO's update, in the policy's inference
while collecting, and in the env's step.

Prints a table and JSON.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from hydra import compose, initialize_config_dir

from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.envs.bench import interleaved_rates, print_report, raw_physics_replay
from mobilemani_rl.envs.step_profile import StageTimer
from mobilemani_rl.rl.config import RLCfg, update_precision
from mobilemani_rl.rl.factory import build_runner
from mobilemani_rl.utils.cli import count, entry_point
from mobilemani_rl.utils.config_store import CONF_DIR, group_options, to_dataclass

ITERATION_PARTS = ("update", "inference", "env_step")  # PPO's update, the policy's actions, the env's step


def bench_preset(preset: str, robot: str, iterations: int, variant: str = "-") -> dict:
    extra = [] if variant == "-" else variant.split()  # "-": the preset alone, as the report prints it
    overrides = [f"rl/ppo={preset}", f"robot={robot}", *extra]
    with initialize_config_dir(config_dir=str(CONF_DIR), version_base="1.3"):
        cfg = compose(config_name="rl", overrides=overrides)
    ppo = to_dataclass(cfg, RLCfg).rl.ppo
    runner = build_runner(cfg, run_dir=None)
    runner.learn(num_learning_iterations=1)  # warm-up: first rollout, normaliser, allocator
    timer = StageTimer(ITERATION_PARTS)
    runner.alg.update = timer.wrap(runner.alg.update, "update")
    runner.alg.act = timer.wrap(runner.alg.act, "inference")
    runner.env.step = timer.wrap(runner.env.step, "env_step")
    start = time.perf_counter()
    runner.learn(num_learning_iterations=iterations)
    seconds = time.perf_counter() - start
    samples = iterations * ppo.num_envs * ppo.num_steps_per_env
    env = runner.env.env
    raw = interleaved_rates(
        {"raw": raw_physics_replay(env, np.random.default_rng(0))}, env.num_envs, seconds=2.0
    )["raw"]
    rate = samples / seconds
    return {
        "preset": preset,
        "robot": robot,
        "variant": variant,
        "num_envs": ppo.num_envs,
        "update_threads": ppo.update_threads,
        "precision": update_precision(ppo),
        "iterations": iterations,
        "samples_per_s": round(rate),
        "raw_env_steps_per_s": round(raw),
        "ppo_over_raw": round(rate / raw, 3),
        # each part's share of the timed iterations; the rest is rsl-rl's storage, returns and logging
        "iteration_shares": {part: round(t / seconds, 3) for part, t in timer.totals.items()},
    }


@entry_point
def main(argv: list[str] | None = None) -> list[dict]:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--presets", nargs="+", default=["cpu", "paper"], choices=group_options("rl/ppo"))
    parser.add_argument("--robots", nargs="+", default=["g1", "xhand"], choices=sorted(ROBOTS))
    parser.add_argument("--iterations", type=count, default=3)
    parser.add_argument("--variants", nargs="+", default=["-"])
    args = parser.parse_args(argv)
    results = [
        bench_preset(p, r, args.iterations, variant)
        for p in args.presets
        for r in args.robots
        for variant in args.variants
    ]
    print_report(
        "ppo",
        results,
        f"{'preset':6} {'robot':6} {'variant':36} {'precision':9} {'envs':>5} {'samples/s':>10} "
        f"{'raw steps/s':>12} {'ppo/raw':>8} {'update':>7}",
        "{preset:6} {robot:6} {variant:36} {precision:9} {num_envs:5d} {samples_per_s:10d} "
        "{raw_env_steps_per_s:12d} {ppo_over_raw:8.3f} {iteration_shares[update]:7.0%}",
    )
    return results


if __name__ == "__main__":
    main()

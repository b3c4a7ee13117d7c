"""Measure grasp stability against the MuJoCo timestep: the scripted policy at several substep counts.

    python scripts/physics_stability.py [--envs 32] [--substeps 2 3 4 6]

For each setting and task: scripted success, simulations with NaN/instability errors, deepest contact
penetration (mm), and how far the held object slips from the palm while being moved (max palm-grasp distance
during the move phase, mm). Prints a Markdown table and JSON.
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from mobilemani_rl.envs.config import EnvCfg, PhysicsCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.rollout import first_episode_success
from mobilemani_rl.scripted.policy import MOVE, ScriptedPolicy
from mobilemani_rl.utils.cli import count

TASKS = (
    ("g1", "test/box", "open"),
    ("g1", "test/can", "pick"),
    ("xhand", "test/box", "open"),
    ("xhand", "test/can", "pick"),
)


def measure(robot: str, obj: str, skill: str, substeps: int, num_envs: int) -> dict:
    cfg = EnvCfg(
        num_envs=num_envs, seed=0, task=TaskCfg(robot, obj, skill), physics=PhysicsCfg(substeps=substeps)
    )
    env = MobileManiEnv(cfg)
    policy = ScriptedPolicy(env)
    worst = {"penetration": 0.0, "slip": 0.0, "unstable": 0}

    def inspect(_) -> None:
        for i in range(env.num_envs):
            data = env.batch.get_data(i)
            if data.ncon:
                worst["penetration"] = max(worst["penetration"], float(-data.contact.dist[: data.ncon].min()))
            if not np.isfinite(data.qpos).all() or env.batch.error(i):
                worst["unstable"] += 1
        moving = (policy.phase == MOVE) & (env.env_times > 0)
        if moving.any():
            worst["slip"] = max(worst["slip"], float(env.distances().hand[moving].max()))

    success = first_episode_success(env, policy, seed=0, on_step=inspect)
    return {
        "robot": robot,
        "object": obj,
        "skill": skill,
        "substeps": substeps,
        "timestep_ms": round(1000 * cfg.physics.timestep, 2),
        "success": float(success.mean()),
        "unstable_sim_steps": worst["unstable"],
        "max_penetration_mm": round(1000 * worst["penetration"], 1),
        "max_slip_mm": round(1000 * worst["slip"], 1),
    }


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--envs", type=count, default=32)
    parser.add_argument("--substeps", nargs="+", type=count, default=[2, 3, 4, 6])
    args = parser.parse_args()
    rows = [measure(*task, s, args.envs) for s in args.substeps for task in TASKS]
    print(
        "| robot | object | skill | substeps | dt (ms) | success | unstable | penetration (mm) | slip (mm) |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['robot']} | {r['object']} | {r['skill']} | {r['substeps']} | {r['timestep_ms']} | "
            f"{r['success']:.2f} | {r['unstable_sim_steps']} | {r['max_penetration_mm']} | "
            f"{r['max_slip_mm']} |"
        )
    print(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()

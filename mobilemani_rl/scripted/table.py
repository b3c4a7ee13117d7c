"""Scripted reference policy success per category, for each robot, on a fixed sample of train objects.

    python -m mobilemani_rl.scripted.table [--robots g1 xhand] [--per-category 3] [--episodes 4]

Each (robot, object, skill) runs `episodes` seeded episodes in one batched env; an episode succeeds if its
latched success flag is set when it ends (the env's own success definition). Prints a
Markdown table (mean success and how many sampled objects reach the 60 % bar, per category and skill) and
JSON.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from mobilemani_rl.assets.objects import CATEGORIES, catalog_ids, get_object
from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.scripted.policy import ScriptedPolicy
from mobilemani_rl.utils.cli import count, entry_point

PASS_RATE = 0.6


def sample_objects(category: str, per_category: int) -> list[str]:
    """Evenly spaced train objects: deterministic, and spread over the category's variants."""
    ids = catalog_ids(category, "train")
    picks = np.unique(np.linspace(0, len(ids) - 1, min(per_category, len(ids))).round().astype(int))
    return [ids[i] for i in picks]


def episode_success(robot: str, object_id: str, skill: str, episodes: int, seed: int) -> float:
    """Fraction of the first `episodes` episodes (one per env) that succeed."""
    env = MobileManiEnv(
        EnvCfg(num_envs=episodes, seed=seed, task=TaskCfg(robot=robot, object=object_id, skill=skill))
    )
    env.reset()
    policy = ScriptedPolicy(env)
    done = np.zeros(episodes, dtype=bool)
    success = np.zeros(episodes, dtype=bool)
    for _ in range(env.max_episode_length):
        result = env.step(policy())
        ended = (result.terminated | result.truncated) & ~done
        success[ended] = result.success_flag[ended]
        done |= ended
        if done.all():
            break
    return float(success.mean())


def run(robots: list[str], categories: list[str], per_category: int, episodes: int, seed: int) -> dict:
    results: dict = {}
    for robot in robots:
        for category in categories:
            for oid in sample_objects(category, per_category):
                for skill in get_object(oid).skills:
                    start = time.time()
                    rate = episode_success(robot, oid, skill, episodes, seed)
                    results.setdefault(robot, {}).setdefault(category, {}).setdefault(skill, {})[oid] = rate
                    print(
                        f"{robot:6s} {oid:22s} {skill:6s} {rate:.2f} ({time.time() - start:.1f}s)",
                        file=sys.stderr,
                        flush=True,
                    )
    return results


def markdown(results: dict, robots: list[str]) -> str:
    header = "| category | skill | " + " | ".join(f"{r} success | {r} objects >= 60%" for r in robots) + " |"
    lines = [header, "|" + "---|" * (2 + 2 * len(robots))]
    first = results[robots[0]]
    for category, skills in first.items():
        for skill in skills:
            cells = []
            for robot in robots:
                rates = list(results[robot][category][skill].values())
                passed = sum(r >= PASS_RATE for r in rates)
                cells += [f"{np.mean(rates):.2f}", f"{passed}/{len(rates)}"]
            lines.append(f"| {category} | {skill} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


@entry_point
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", default=["g1", "xhand"], choices=sorted(ROBOTS))
    parser.add_argument("--categories", nargs="+", default=list(CATEGORIES))
    parser.add_argument("--per-category", type=count, default=3)
    parser.add_argument("--episodes", type=count, default=4)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, help="also write the JSON here")
    args = parser.parse_args()
    results = run(args.robots, args.categories, args.per_category, args.episodes, args.seed)
    print(markdown(results, args.robots))
    text = json.dumps(results, indent=1)
    print(text)
    if args.json:
        args.json.write_text(text)


if __name__ == "__main__":
    main()

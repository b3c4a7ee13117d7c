"""Digests of seeded rollouts, to show that a change meant to leave the env's behaviour alone (a speed-up)
does: sha256 over every step's observations, rewards, terminations and truncations of random actions, for
each robot with a mobile and a fixed base. Equal digests before and after a change, on the same machine and
software, mean bit-identical rollouts (different CPUs may round differently).

    python -m mobilemani_rl.envs.rollout_digest [--robots g1 xhand] [--envs 32] [--steps 400] [--seed 0]

The default 400 steps run past the 300-step episode, so resets are part of the digest. Prints JSON.
"""

from __future__ import annotations

import argparse
import hashlib
import json

import numpy as np

from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.utils.cli import count, entry_point


def rollout_digest(
    robot: str,
    fixed_base: bool,
    num_envs: int,
    steps: int,
    seed: int,
    obj: str = "test/box",
    skill: str = "open",
) -> str:
    task = TaskCfg(robot=robot, object=obj, skill=skill)
    env = MobileManiEnv(EnvCfg(num_envs=num_envs, seed=seed, fixed_base=fixed_base, task=task))
    rng = np.random.default_rng(seed)
    digest = hashlib.sha256(env.reset().tobytes())
    for _ in range(steps):
        result = env.step(rng.uniform(-1.0, 1.0, (num_envs, env.num_actions)))
        for array in (result.obs, result.reward, result.terminated, result.truncated):
            digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


@entry_point
def main(argv: list[str] | None = None) -> dict[str, str]:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--robots", nargs="+", default=["g1", "xhand"], choices=sorted(ROBOTS))
    parser.add_argument("--envs", type=count, default=32)
    parser.add_argument("--steps", type=count, default=400)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    digests = {
        f"{robot} {'fixed' if fixed else 'mobile'} base": rollout_digest(
            robot, fixed, args.envs, args.steps, args.seed
        )
        for robot in args.robots
        for fixed in (False, True)
    }
    print(
        json.dumps({"envs": args.envs, "steps": args.steps, "seed": args.seed, "digests": digests}, indent=2)
    )
    return digests


if __name__ == "__main__":
    main()

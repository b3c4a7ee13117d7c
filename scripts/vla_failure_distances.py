"""Where a closed-loop evaluation's episodes stop: rerun chosen rooms of a finished evaluation with the same
seeds and print, per episode, success, the closest the grasp point came to its goal and the closest palm
approach, split into its vertical part (palm minus grasp point, negative: below) and its horizontal one; with
`--teacher`, also how far the executed actions were from what a PPO teacher would do in the
same states (mean |executed - teacher| per action dimension and step, the teacher's action clipped as the
env clips it).

    python -m scripts.vla_failure_distances outputs/recipe/eval/g1/vla_open/config.json tabletop/17 \
        [--teacher outputs/demo/rl/g1/test/box/open/model_99.pt]

A goal distance equal to the task's start distance means the object never moved (e.g. a lid never lifted).
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # this command renders offscreen; mujoco reads it when imported

import argparse
import json
from pathlib import Path

import numpy as np
from omegaconf import OmegaConf

from mobilemani_rl.envs.mobilemani_env import MobileManiEnv, StepResult
from mobilemani_rl.envs.tasks import Combination, select_combinations
from mobilemani_rl.utils.config_store import to_dataclass
from mobilemani_vla.eval.config import EvalCfg
from mobilemani_vla.eval.evaluate import block_env, run_block
from mobilemani_vla.eval.policies.base import EvalPolicy, Observation
from mobilemani_vla.eval.policies.factory import build_policy
from mobilemani_vla.eval.policies.privileged import TeacherEvalPolicy


class AskingTheTeacher(EvalPolicy):
    """The evaluated policy, which acts; the teacher is asked at the same observations and its action kept."""

    def __init__(self, policy: EvalPolicy, teacher: TeacherEvalPolicy) -> None:
        self.policy, self.teacher = policy, teacher
        self.name, self.action_frame = policy.name, policy.action_frame
        self.image_size, self.action_dim, self.chunk_length = (
            policy.image_size,
            policy.action_dim,
            policy.chunk_length,
        )
        self.inputs = policy.inputs | teacher.inputs
        self.asked: np.ndarray | None = None

    def start(self, env: MobileManiEnv, seed: int) -> None:
        self.policy.start(env, seed)
        self.teacher.start(env, seed)

    def act(self, obs: Observation) -> np.ndarray:
        self.asked = np.clip(self.teacher.act(obs)[:, 0], -1.0, 1.0)
        return self.policy.act(obs)


def closest_in_first_batch(cfg: EvalCfg, policy: EvalPolicy, combo: Combination) -> dict:
    """The combination's first evaluation batch as the evaluation ran it, with each episode's closest
    distances."""
    env, seed = block_env(cfg, combo, 0)
    goal = np.full(env.num_envs, np.inf)
    hand = np.full(env.num_envs, np.inf)
    palm_offset = np.zeros((env.num_envs, 3))  # palm minus grasp point at the closest approach
    gap = np.zeros((env.num_envs, env.num_actions))
    steps = np.zeros(env.num_envs)
    live = np.ones(env.num_envs, dtype=bool)

    def track(result: StepResult) -> None:
        # A finished env has been reset already: only envs still in their first episode count.
        reached = env.task_distances
        goal[live] = np.minimum(goal[live], reached.goal[live])
        closer = live & (reached.hand < hand)
        hand[closer] = reached.hand[closer]
        palm_offset[closer] = env.frames.palm_pos[closer] - env.frames.grasp_pos[closer]
        live[result.done_ids] = False
        if isinstance(policy, AskingTheTeacher):  # the action each live env executed this step
            gap[live] += np.abs(env.last_action[live] - policy.asked[live])
            steps[live] += 1

    stats = run_block(cfg, policy, combo, env, seed, track)
    out = {
        "combination": combo.name,
        "success": stats.success.astype(int).tolist(),
        "closest_goal_cm": np.round(goal * 100, 1).tolist(),
        "closest_palm_cm": np.round(hand * 100, 1).tolist(),
        "closest_palm_vertical_cm": np.round(palm_offset[:, 2] * 100, 1).tolist(),
        "closest_palm_horizontal_cm": np.round(np.linalg.norm(palm_offset[:, :2], axis=1) * 100, 1).tolist(),
    }
    if isinstance(policy, AskingTheTeacher):
        out["teacher_gap_per_dim"] = np.round(gap / np.maximum(steps, 1)[:, None], 2).tolist()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("config", type=Path, help="config.json of a finished evaluation run")
    parser.add_argument("scenes", nargs="+", help="scene ids to rerun, e.g. tabletop/17")
    parser.add_argument("--teacher", help="a PPO teacher checkpoint to ask at every state the policy reaches")
    args = parser.parse_args()
    cfg = to_dataclass(OmegaConf.create(json.loads(args.config.read_text())["eval"]), EvalCfg)
    policy = build_policy(cfg.policy)
    if args.teacher:
        policy = AskingTheTeacher(policy, TeacherEvalPolicy(args.teacher))
    for combo in select_combinations(cfg.robot, cfg.subset):
        if combo.scene in args.scenes:
            print(json.dumps(closest_in_first_batch(cfg, policy, combo)), flush=True)


if __name__ == "__main__":
    main()

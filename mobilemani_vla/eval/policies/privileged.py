"""Reference policies with privileged access to the simulator: the scripted policy,
PPO teachers, random actions.

They act in the world frame with chunks of one action, so the ensemble reduces to executing that action.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.rl.teacher import (
    TeacherPolicy,
    check_teacher_robot,
    find_every_teacher,
    find_teacher_checkpoint,
    load_teacher,
)
from mobilemani_rl.scripted.policy import ScriptedPolicy
from mobilemani_vla.eval.policies.base import PRIVILEGED_STATE, EvalPolicy, Observation


class PrivilegedPolicy(EvalPolicy):
    """Acts from the simulator's state, one action per chunk."""

    chunk_length = 1


class ScriptedEvalPolicy(PrivilegedPolicy):
    """mobilemani_rl.scripted.policy, which reads the task state of the env it is bound to."""

    name = "scripted"

    def start(self, env: MobileManiEnv, seed: int) -> None:
        self.policy = ScriptedPolicy(env)

    def act(self, obs: Observation) -> np.ndarray:
        return self.policy()[:, None]


class RandomPolicy(PrivilegedPolicy):
    """Uniform actions in [-1, 1]: the floor every benchmark entrant should beat."""

    name = "random"
    inputs = frozenset({PRIVILEGED_STATE})  # read only for the batch size

    def start(self, env: MobileManiEnv, seed: int) -> None:
        self.rng = np.random.default_rng(seed)
        self.action_dim = env.num_actions

    def act(self, obs: Observation) -> np.ndarray:
        return self.rng.uniform(-1.0, 1.0, size=(len(obs[PRIVILEGED_STATE]), 1, self.action_dim))


class TeacherEvalPolicy(PrivilegedPolicy):
    """Deterministic actor of a PPO checkpoint on the privileged RL observation: the teacher's evaluation
    (mobilemani_rl.rl.eval) and data collection act through the same TeacherPolicy.

    `checkpoint` fixes one checkpoint; otherwise each task uses the newest model_*.pt under
    <runs_dir>/<robot>/<object>/<skill> (the layout of mobilemani_rl.rl.train), else under its category's run
    <runs_dir>/<robot>/<category>/<skill>.
    """

    name = "teacher"
    inputs = frozenset({PRIVILEGED_STATE})

    def __init__(self, checkpoint: str | None = None, runs_dir: str = "outputs/rl") -> None:
        self.checkpoint = None if checkpoint is None else Path(checkpoint)
        self.runs_dir = Path(runs_dir)
        self.loaded: Path | None = None

    def _checkpoint_for(self, env: MobileManiEnv) -> Path:
        if self.checkpoint is not None:
            return self.checkpoint
        task = env.cfg.task
        return find_teacher_checkpoint(self.runs_dir, task.robot, task.object, task.skill)

    def check_tasks(self, tasks: set[tuple[str, str, str]]) -> dict[str, str]:
        if self.checkpoint is None:  # stops naming every missing teacher
            found = find_every_teacher(self.runs_dir, tasks, "policy.runs_dir")
            return {" ".join(task): str(path) for task, path in found.items()}
        check_teacher_robot(self.checkpoint, {robot for robot, _, _ in tasks})
        return {}

    def start(self, env: MobileManiEnv, seed: int) -> None:
        checkpoint = self._checkpoint_for(env)
        if checkpoint != self.loaded:
            _, self.actor = load_teacher(checkpoint, env=env)
            self.loaded = checkpoint
        self.teacher = TeacherPolicy(env, self.actor)

    def act(self, obs: Observation) -> np.ndarray:
        return self.teacher.act(obs[PRIVILEGED_STATE])[:, None]

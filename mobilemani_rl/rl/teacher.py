"""A trained PPO teacher, the one way to use it: where its run lives, its checkpoint, its deterministic actor.

Evaluation (`mobilemani_rl.rl.eval`), data collection (`mobilemani_data.teachers`) and the closed-loop harness
(`mobilemani_vla.eval.policies.privileged`) all load teachers through `load_teacher` and act through
`TeacherPolicy`, and step their episodes through `mobilemani_rl.envs.rollout`, so a teacher scores the same in
its own evaluation and in the harness under the same env config and seed. Checkpoints are read with
`weights_only=True` (`MobileManiRunner.load`), so a checkpoint file never runs code.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np
import torch
from omegaconf import DictConfig, OmegaConf
from tensordict import TensorDict

from mobilemani_rl.assets.objects import get_object
from mobilemani_rl.envs.batched import BatchedEnv
from mobilemani_rl.rl.factory import build_runner
from mobilemani_rl.rl.run_dir import CONFIG, RESULT, latest_checkpoint
from mobilemani_rl.utils.errors import InputError, MissingFileError
from mobilemani_rl.utils.io import read_json


def teacher_run_dir(runs_dir: str | Path, robot: str, object_id: str, skill: str) -> Path:
    """<runs_dir>/<robot>/<object or category>/<skill>: where `mobilemani_rl.rl.train` writes a task's run."""
    return Path(runs_dir) / robot / object_id / skill


def find_teacher_checkpoint(runs_dir: str | Path, robot: str, object_id: str, skill: str) -> Path:
    """The newest model_*.pt of the object's own run, else of its category's run (a multi-object policy
    trained with task.object=<category>, which acts on any object of the category);
    a clear error naming both."""
    category_name = get_object(object_id).category
    own = teacher_run_dir(runs_dir, robot, object_id, skill)
    category = teacher_run_dir(runs_dir, robot, category_name, skill)
    for run_dir in (own, category):
        if (found := latest_checkpoint(run_dir)) is not None:
            return found
    raise MissingFileError(
        f"no teacher checkpoint model_*.pt in {own} nor in its category's run {category} (train "
        f"one with python -m mobilemani_rl.rl.train robot={robot} task.object={object_id} or "
        f"task.object={category_name} task.skill={skill})"
    )


def find_every_teacher(
    runs_dir: str | Path, tasks: Iterable[tuple[str, str, str]], key: str
) -> dict[tuple[str, str, str], Path]:
    """Each (robot, object, skill) task's teacher checkpoint, looked up before a long run starts: missing
    ones stop it with one error naming them all (`key`: the setting that gave `runs_dir`), not midway."""
    found, missing = {}, []
    for task in sorted(set(tasks)):
        try:
            found[task] = find_teacher_checkpoint(runs_dir, *task)
        except MissingFileError:
            missing.append(f"{task[1]} {task[2]}")
    if missing:
        shown = ", ".join(missing[:4]) + (", ..." if len(missing) > 4 else "")
        raise MissingFileError(
            f"no PPO teacher in {key}={runs_dir} for {len(missing)} of {len(found) + len(missing)} "
            f"object-skill tasks ({shown}): each needs a run <runs_dir>/<robot>/<object>/<skill> or its "
            "category's <runs_dir>/<robot>/<category>/<skill>. `make teachers ROBOT=<robot>` trains every "
            f"category's into outputs/teachers (then {key}=outputs/teachers); or select fewer "
            "(subset.categories=[...], subset.skills=[...])"
        )
    return found


def trained_success(run_dir: Path) -> float | None:
    """The success rate the run reached in training (its result.json); None while it has not finished."""
    path = run_dir / RESULT
    return read_json(path).get("train_success") if path.is_file() else None


def run_config(checkpoint: Path) -> DictConfig:
    """The config the checkpoint's run was trained with (its run directory's config.yaml)."""
    path = checkpoint.parent / CONFIG
    if not path.is_file():
        raise MissingFileError(
            f"{checkpoint} has no {CONFIG} beside it; it is not a mobilemani_rl.rl.train run"
        )
    return OmegaConf.load(path)


def check_checkpoint_file(checkpoint: Path) -> None:
    """A teacher checkpoint is a model_*.pt file; a run directory given instead is named with its newest."""
    if checkpoint.is_file():
        return
    if checkpoint.is_dir():
        newest = latest_checkpoint(checkpoint)
        hint = f"its newest checkpoint is {newest}" if newest else "it holds no model_*.pt"
        raise MissingFileError(f"teacher checkpoint {checkpoint} is a directory; {hint}")
    raise MissingFileError(f"teacher checkpoint {checkpoint} does not exist")


def check_teacher_robot(checkpoint: Path, robots: Iterable[str]) -> None:
    """A fixed teacher checkpoint exists and was trained for every robot it is asked to act for."""
    check_checkpoint_file(checkpoint)
    trained = run_config(checkpoint).task.robot
    if others := sorted(set(robots) - {trained}):
        raise InputError(
            f"teacher checkpoint {checkpoint} was trained for robot={trained}, not robot={','.join(others)}; "
            "evaluate it with the robot it was trained for"
        )


def load_teacher(
    checkpoint: Path,
    env: BatchedEnv | None = None,
    num_envs: int | None = None,
    cfg: DictConfig | None = None,
) -> tuple[BatchedEnv, torch.nn.Module]:
    """The teacher's env and deterministic actor. The actor acts in `env` when given, else in a new env built
    from `cfg` (default: the run's own config) with `num_envs` envs; the teacher was trained with that
    config's physics and action scales. It runs on the CPU beside MuJoCo, wherever it was trained."""
    check_checkpoint_file(checkpoint)
    runner = build_runner(
        cfg if cfg is not None else run_config(checkpoint),
        run_dir=None,
        num_envs=num_envs,
        env=env,
        device="cpu",
    )
    runner.load(str(checkpoint))
    return runner.env.env, runner.get_inference_policy()


class TeacherPolicy:
    """A teacher's actor reading the env's current observation: (num_envs, action_dim) actions per call."""

    def __init__(self, env: BatchedEnv, actor: torch.nn.Module) -> None:
        self.env, self.actor = env, actor

    @torch.inference_mode()
    def act(self, obs: np.ndarray) -> np.ndarray:
        """The actor's actions for any (num_obs,) rows, e.g. an observation with one input replaced."""
        return self.actor(TensorDict({"policy": torch.from_numpy(obs)}, batch_size=[obs.shape[0]])).numpy()

    def __call__(self) -> np.ndarray:
        return self.act(self.env.obs)

"""Teachers for collection: the scripted reference policy, or a trained PPO checkpoint."""

from __future__ import annotations

from dataclasses import dataclass

from mobilemani_data.config import TeacherCfg
from mobilemani_data.recorder import Policy
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.tasks import Combination, recording_env_cfg
from mobilemani_rl.scripted.policy import ScriptedPolicy
from mobilemani_rl.utils.errors import MissingFileError, check_choice

KINDS = ("scripted", "ppo")


@dataclass
class Teacher:
    env: MobileManiEnv
    policy: Policy
    name: str  # "scripted" or the checkpoint path


def kind_of(name: str) -> str:
    """The kind of teacher a shard header's `teacher` name stands for."""
    return "scripted" if name == "scripted" else "ppo"


def current_teacher(cfg: TeacherCfg, combo: Combination, recorded: str) -> str:
    """The teacher name a collection would record for the combination now: 'scripted', or the PPO checkpoint
    the lookup finds (a teacher trained on since is another one). A shard whose PPO teacher has gone keeps the
    one it `recorded`."""
    if cfg.kind == "scripted":
        return "scripted"
    from mobilemani_rl.rl.teacher import find_teacher_checkpoint  # the RL stack, for PPO teachers only

    try:
        return str(find_teacher_checkpoint(cfg.runs_dir, combo.robot, combo.object_id, combo.skill))
    except MissingFileError:
        return recorded if kind_of(recorded) == "ppo" else "ppo"


def task_of(combo: Combination) -> TaskCfg:
    return TaskCfg(robot=combo.robot, object=combo.object_id, skill=combo.skill, scene=combo.scene)


def build_teacher(cfg: TeacherCfg, combo: Combination, env_base: EnvCfg, num_envs: int, seed: int) -> Teacher:
    check_choice(cfg.kind, KINDS, "teacher kind")
    if cfg.kind == "scripted":
        env = MobileManiEnv(recording_env_cfg(env_base, task_of(combo), num_envs, seed))
        return Teacher(env, ScriptedPolicy(env), "scripted")
    return _ppo_teacher(cfg, combo, env_base, num_envs, seed)


def teachable_combinations(cfg: TeacherCfg, combos: list[Combination]) -> tuple[list[Combination], list[str]]:
    """Look up every PPO teacher the combinations need before anything is collected: a missing one stops the
    run with one error naming them all, instead of a stop midway through a long collection. Combinations whose
    teacher trained below `teacher.min_train_success` are left out (as the reference does), with one line per
    such teacher run instead of one per combination."""
    if cfg.kind != "ppo":
        return combos, []
    from mobilemani_rl.rl.teacher import find_every_teacher, trained_success

    checkpoints = find_every_teacher(
        cfg.runs_dir, ((c.robot, c.object_id, c.skill) for c in combos), "teacher.runs_dir"
    )
    weak_runs = {}
    for task, checkpoint in checkpoints.items():
        run_dir = checkpoint.parent
        if (rate := trained_success(run_dir)) is not None and rate < cfg.min_train_success:
            weak_runs[task] = f"{run_dir} trained to success {rate:.2f}"
    kept = [c for c in combos if (c.robot, c.object_id, c.skill) not in weak_runs]
    notes = [
        f"left out: {run} < teacher.min_train_success={cfg.min_train_success} (lower it, e.g. "
        "teacher.min_train_success=0, to collect with it anyway)"
        for run in sorted(set(weak_runs.values()))
    ]
    return kept, notes


def _ppo_teacher(cfg: TeacherCfg, combo: Combination, env_base: EnvCfg, num_envs: int, seed: int) -> Teacher:
    # Imported here: the RL stack (torch, rsl-rl) is only needed for PPO teachers.
    from mobilemani_rl.rl.teacher import (
        TeacherPolicy,
        find_teacher_checkpoint,
        load_teacher,
        run_config,
    )

    checkpoint = find_teacher_checkpoint(cfg.runs_dir, combo.robot, combo.object_id, combo.skill)
    # The teacher acts in the env it was trained in (physics, action scales), placed in the recording scene
    # (with the collection's table heights), on this combination's object (a category run's config names the
    # category), on as many physics threads as this collection gives it: the thread count does not change a
    # rollout.
    run_cfg = run_config(checkpoint)
    run_cfg.task.object = combo.object_id
    run_cfg.task.scene = combo.scene
    run_cfg.env.physics.nthread = env_base.physics.nthread
    run_cfg.env.reset.recording = True
    run_cfg.env.reset.table_height_jitter = env_base.reset.table_height_jitter
    run_cfg.logger = "tensorboard"
    env, actor = load_teacher(checkpoint, num_envs=num_envs, cfg=run_cfg)
    env.cfg.seed = seed
    return Teacher(env, TeacherPolicy(env, actor), str(checkpoint))

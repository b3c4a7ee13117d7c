"""DART collection: the env executes the teacher's action plus noise, the dataset keeps the clean action."""

import numpy as np
from data_helpers import tiny_cfg

from mobilemani_data.recorder import collect_successes
from mobilemani_data.teachers import build_teacher
from mobilemani_rl.envs.tasks import select_combinations


def test_noisy_execution_records_the_clean_teacher_action(tmp_path):
    cfg = tiny_cfg(tmp_path, "collect.action_noise=0.3")
    combo = select_combinations(cfg.robot, cfg.subset)[0]
    teacher = build_teacher(cfg.teacher, combo, cfg.env, 4, seed=3)
    clean: list[np.ndarray] = []
    executed: list[np.ndarray] = []

    def policy() -> np.ndarray:
        clean.append(np.clip(teacher.policy(), -1.0, 1.0))
        return clean[-1]

    step = teacher.env.step
    teacher.env.step = lambda actions: (executed.append(actions.copy()), step(actions))[1]
    rollouts = collect_successes(teacher.env, policy, 2, 3000, seed=3, action_noise=cfg.collect.action_noise)

    assert len(rollouts.episodes) == 2  # the scripted teacher still succeeds under the noise
    for episode in rollouts.episodes:
        slot, start = episode.attrs["env_slot"], episode.attrs["start_step"]
        steps = range(start, start + episode.length - 1)  # the last frame's action was never executed
        recorded = episode.arrays["action"][: episode.length - 1]
        assert np.array_equal(recorded, np.stack([clean[t][slot] for t in steps]))
        noise = np.stack([executed[t][slot] for t in steps]) - recorded
        assert 0.15 < noise.std() < 0.3  # clipping to [-1, 1] only shrinks the 0.3 noise

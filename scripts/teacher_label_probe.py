"""What makes a PPO teacher's DART demonstrations hard to imitate: its reliance on inputs a VLA never sees.

    python -m scripts.teacher_label_probe outputs/demo/rl [more runs dirs ...] [--scripted] --out probe.json

For each runs directory holding a g1 test/box open teacher (the demo's task), in the demo's first train rooms,
with the demo's DART noise:
- sensitivity: the mean |change| of the teacher's action when the observation's last action (the perturbed
  one the env executed) is replaced by the teacher's own clean previous action, when its time encoding is
  moved one second later, and when its velocities and accelerations are zeroed; beside it, the action's own
  mean step-to-step change;
- roughness of the recorded labels, mean |a[t+1] - a[t]|, raw and smoothed as `export.label_window` does;
  `--scripted` adds the scripted teacher's, whose labels a VLA learns well.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from mobilemani_data.config import TeacherCfg
from mobilemani_data.convert import smoothed_labels
from mobilemani_data.recorder import collect_successes
from mobilemani_data.teachers import build_teacher
from mobilemani_rl.envs.config import EnvCfg
from mobilemani_rl.envs.observations import TIME_ENCODING_DIM, time_encoding
from mobilemani_rl.envs.tasks import SubsetCfg, select_combinations

ACTION_NOISE = 0.3  # the demo's collect.action_noise
WINDOWS = (1, 5, 9, 15)  # label smoothing windows measured
SECOND = 30  # control steps


def label_roughness(episodes: list, window: int) -> float:
    """Mean |a[t+1] - a[t]| of the labels as exported with `export.ppo_label_window=window`."""
    steps = [np.abs(np.diff(smoothed_labels(ep.arrays["action"], window), axis=0)).mean() for ep in episodes]
    return float(np.mean(steps))


def velocity_columns(env) -> list[int]:
    """The observation's velocity and acceleration entries (reference order: time, last action, palm pos /
    euler / linvel / angvel, the same 12 per finger, joint pos / vel / acc), which one camera frame does not
    show."""
    fingers, joints = len(env.index.finger_sites), len(env.joint_limits)
    palm = TIME_ENCODING_DIM + env.num_actions
    columns = [c for part in range(1 + fingers) for c in range(palm + 12 * part + 6, palm + 12 * part + 12)]
    joint_block = palm + 12 * (1 + fingers)
    return columns + [joint_block + 3 * j + k for j in range(joints) for k in (1, 2)]


class ProbedTeacher:
    """The teacher's action, and what it would have been with its last-action, time or velocity input
    replaced."""

    def __init__(self, teacher) -> None:
        self.env, self.policy = teacher.env, teacher.policy
        n, a = self.env.num_envs, self.env.num_actions
        self.previous_clean = np.zeros((n, a))
        self.last_action = slice(TIME_ENCODING_DIM, TIME_ENCODING_DIM + a)
        self.velocities = velocity_columns(self.env)
        self.changes: dict[str, list[float]] = {
            k: [] for k in ("last_action", "time", "velocities", "own_step")
        }

    def _act(self, obs: np.ndarray) -> np.ndarray:
        return self.policy.act(obs).astype(np.float64)

    def __call__(self) -> np.ndarray:
        env, obs = self.env, self.env.obs
        fresh = env.episode_length_buf == 0
        self.previous_clean[fresh] = 0.0
        action = self._act(obs)
        clean_last = obs.copy()
        clean_last[:, self.last_action] = np.clip(self.previous_clean, -1.0, 1.0)
        later = obs.copy()
        later[:, :TIME_ENCODING_DIM] = time_encoding(env.env_times + SECOND)
        still = obs.copy()
        still[:, self.velocities] = 0.0
        running = ~fresh
        if running.any():
            for key, other in (("last_action", clean_last), ("time", later), ("velocities", still)):
                self.changes[key].append(float(np.abs(self._act(other) - action)[running].mean()))
            self.changes["own_step"].append(float(np.abs(action - self.previous_clean)[running].mean()))
        self.previous_clean = action.copy()
        return action


def probe(teacher_cfg: TeacherCfg, rooms: int, episodes: int, num_envs: int) -> dict:
    subset = SubsetCfg(objects=["test/box"], skills=["open"], scenes_per_object=rooms, episodes=episodes)
    combos = select_combinations("g1", subset)
    kept, attempts = [], 0
    changes: dict[str, list[float]] = {}
    for combo in combos:
        seed = combo.seed(0)
        teacher = build_teacher(teacher_cfg, combo, EnvCfg(), num_envs, seed)
        policy = ProbedTeacher(teacher) if teacher_cfg.kind == "ppo" else teacher.policy
        rollouts = collect_successes(teacher.env, policy, episodes, 6000, seed, ACTION_NOISE)
        kept += rollouts.episodes
        attempts += rollouts.attempts
        for key, values in getattr(policy, "changes", {}).items():
            changes.setdefault(key, []).extend(values)
    return {
        "teacher": teacher_cfg.runs_dir if teacher_cfg.kind == "ppo" else "scripted",
        "rooms": len(combos),
        "kept": len(kept),
        "attempts": attempts,
        "mean_length": float(np.mean([ep.length for ep in kept])),
        "sensitivity": {key: float(np.mean(values)) for key, values in changes.items()},
        "label_roughness": {str(w): label_roughness(kept, w) for w in WINDOWS},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs_dirs", nargs="*", type=Path)
    parser.add_argument("--scripted", action="store_true", help="the scripted teacher too, for reference")
    parser.add_argument("--rooms", type=int, default=4)
    parser.add_argument("--episodes", type=int, default=10)
    parser.add_argument("--num-envs", type=int, default=16)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    teachers = [TeacherCfg(kind="ppo", runs_dir=str(d)) for d in args.runs_dirs]
    if args.scripted:
        teachers.append(TeacherCfg(kind="scripted"))
    results = [probe(t, args.rooms, args.episodes, args.num_envs) for t in teachers]
    args.out.write_text(json.dumps(results, indent=2) + "\n")
    windows = " | ".join(f"roughness w={w}" for w in WINDOWS)
    print(
        "| teacher | kept / ended episodes | d(action): last action clean | time +1 s | velocities zeroed | "
        f"own step | {windows} |"
    )
    print("|---|---:|---:|---:|---:|---:|" + "---:|" * len(WINDOWS))
    for r in results:
        s = r["sensitivity"]
        sens = " | ".join(
            f"{s[k]:.4f}" if k in s else "-" for k in ("last_action", "time", "velocities", "own_step")
        )
        rough = " | ".join(f"{r['label_roughness'][str(w)]:.4f}" for w in WINDOWS)
        print(f"| {r['teacher']} | {r['kept']}/{r['attempts']} | {sens} | {rough} |")


if __name__ == "__main__":
    main()

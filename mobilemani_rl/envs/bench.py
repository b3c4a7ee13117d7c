"""Environment throughput against the raw physics limit, measured in the same run.

    python -m mobilemani_rl.envs.bench [--robots g1 xhand] [--envs 64 256 1024] [--seconds 3] [--profile 200]

env: `MobileManiEnv.step` with random actions (IK, physics, observations, rewards, resets).
raw: the same compiled model in a `mujoco.batch.Batch` of the same size and thread count replaying the joint
targets the env produced (same start state, same motion), in one `Batch.rollout` call per 32 control steps, so
with no Python work between steps.
physics: the same replay in the env's own physics calls (two per control step, velocities read between them):
the env's ceiling, were its Python work free.
All report control steps per second (x substeps = physics steps per second), best of interleaved trials.
--profile N: then each stage's share of N more steps of the same env through the rsl-rl adapter
(mobilemani_rl.envs.step_profile). Prints tables and JSON.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import mujoco.batch
import numpy as np

from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.envs.step_profile import profile_step, profile_table
from mobilemani_rl.utils.cli import count, entry_point, seconds


def interleaved_rates(
    steppers: dict[str, tuple[Callable[[], None], int]], n: int, seconds: float, trials: int = 6
) -> dict[str, float]:
    """Best env-steps/s of each stepper (a call and the control steps it advances); trials alternate between
    steppers so that background load drifts affect them alike."""
    for step, _ in steppers.values():
        step()
    best = dict.fromkeys(steppers, 0.0)
    budget = seconds / (trials * len(steppers))
    for _ in range(trials):
        for name, (step, per_call) in steppers.items():
            start, done = time.perf_counter(), 0
            while time.perf_counter() - start < budget:
                step()
                done += per_call
            best[name] = max(best[name], done * n / (time.perf_counter() - start))
    return best


@dataclass(frozen=True)
class ControlRecording:
    """The joint targets an env sent over `segment` control steps of random actions, and the state it
    started from: replaying them keeps the physics work equal (moving arms, contacts), where a batch stepped
    with fixed controls settles and measures a cheaper, idle robot."""

    start: dict[str, np.ndarray]
    controls: np.ndarray  # (num_envs, segment, nu)

    @property
    def segment(self) -> int:
        return self.controls.shape[1]

    def load(self, batch: mujoco.batch.Batch) -> None:
        for field, value in self.start.items():
            batch.bind(field)[:] = value


def record_controls(env: MobileManiEnv, rng: np.random.Generator, segment: int = 32) -> ControlRecording:
    start = {f: env.batch.bind(f).copy() for f in ("qpos", "qvel", "ctrl", "mocap_pos", "mocap_quat")}
    controls = np.empty((env.num_envs, segment, env.model.nu))
    for k in range(segment):
        env.step(rng.uniform(-1, 1, (env.num_envs, env.num_actions)))
        controls[:, k] = env.view.ctrl
    return ControlRecording(start, controls)


def rollout_replay(env: MobileManiEnv, recording: ControlRecording) -> tuple[Callable[[], None], int]:
    """The raw physics limit: the recording replayed in a fresh `mujoco.batch.Batch` of the env's model, size
    and threads with one `Batch.rollout` call (no Python between steps), from the same start state."""
    substeps = env.cfg.physics.substeps
    per_substep = np.repeat(recording.controls, substeps, axis=1)
    raw = mujoco.batch.Batch(env.model, env.num_envs, nthread=env.cfg.physics.nthread)

    def replay() -> None:
        recording.load(raw)
        raw.rollout(
            recording.segment * substeps, control=per_substep, control_spec=mujoco.mjtState.mjSTATE_CTRL
        )

    return replay, recording.segment


def stepped_replay(env: MobileManiEnv, recording: ControlRecording) -> tuple[Callable[[], None], int]:
    """The env's own physics calls alone: the recording replayed in a persistent batch as `MobileManiEnv.step`
    steps it, per control step all substeps but the last, a read of the joint velocities, then the last. Its
    rate is the most the env can reach with its Python work free; below the raw limit, as the batch's threads
    meet twice per control step instead of once per rollout."""
    batch = mujoco.batch.Batch(env.model, env.num_envs, nthread=env.cfg.physics.nthread, persistent=True)
    ctrl, qvel = batch.bind("ctrl"), batch.bind("qvel")
    substeps, dofs = env.cfg.physics.substeps, env.frame_reader.active_dof

    def replay() -> None:
        recording.load(batch)
        batch.forward(stage=mujoco.mjtStage.mjSTAGE_VEL)
        for k in range(recording.segment):
            ctrl[:] = recording.controls[:, k]
            if substeps > 1:
                batch.step(nstep=substeps - 1)
            np.take(qvel, dofs, axis=1)  # the env's read of the velocities, timed with the physics
            batch.step(nstep=1, stage=mujoco.mjtStage.mjSTAGE_VEL)

    return replay, recording.segment


def raw_physics_replay(
    env: MobileManiEnv, rng: np.random.Generator, segment: int = 32
) -> tuple[Callable[[], None], int]:
    """`rollout_replay` of `segment` control steps the env takes now."""
    return rollout_replay(env, record_controls(env, rng, segment))


def bench_task(
    robot: str,
    num_envs: int,
    seconds: float,
    profile_steps: int = 0,
    obj: str = "test/box",
    skill: str = "open",
) -> dict:
    env = MobileManiEnv(EnvCfg(num_envs=num_envs, task=TaskCfg(robot=robot, object=obj, skill=skill)))
    env.reset()
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (64, num_envs, env.num_actions))
    counter = iter(range(1 << 62))

    def env_step() -> None:
        env.step(actions[next(counter) % len(actions)])

    substeps = env.cfg.physics.substeps
    recording = record_controls(env, rng)
    steppers = {
        "env": (env_step, 1),
        "raw": rollout_replay(env, recording),
        "physics": stepped_replay(env, recording),
    }
    rates = interleaved_rates(steppers, num_envs, seconds)
    env_rate, raw_rate = rates["env"], rates["raw"]
    # the rates are measured; the env's last use is the profile, which instruments it
    profile = {"profile": profile_step(env, profile_steps)} if profile_steps else {}
    return {
        "robot": robot,
        "num_envs": num_envs,
        "substeps": substeps,
        "timestep": env.model.opt.timestep,
        "env_steps_per_s": round(env_rate),
        "raw_steps_per_s": round(raw_rate),
        "raw_physics_steps_per_s": round(raw_rate * substeps),
        "env_over_raw": round(env_rate / raw_rate, 3),
        "physics_steps_per_s": round(rates["physics"]),
        "physics_over_raw": round(rates["physics"] / raw_rate, 3),
        **profile,
    }


def print_report(benchmark: str, results: list[dict], header: str, row: str) -> None:
    """A table (`row` formatted with each result's keys under `header`), then the results as JSON."""
    print(header)
    for r in results:
        print(row.format(**r))
    print(json.dumps({"benchmark": benchmark, "results": results}, indent=2))


@entry_point
def main(argv: list[str] | None = None) -> list[dict]:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--robots", nargs="+", default=["g1", "xhand"], choices=sorted(ROBOTS))
    parser.add_argument("--envs", nargs="+", type=count, default=[64, 256, 1024])
    parser.add_argument("--seconds", type=seconds, default=6.0, help="timing budget per (robot, envs) pair")
    parser.add_argument("--profile", type=count, default=0, metavar="N", help="profile N steps per pair")
    args = parser.parse_args(argv)
    results = [bench_task(r, n, args.seconds, args.profile) for r in args.robots for n in args.envs]
    if args.profile:
        print(profile_table(results) + "\n")
    print_report(
        "sim",
        results,
        f"{'robot':6} {'envs':>5} {'env steps/s':>12} {'raw steps/s':>12} {'env/raw':>8} {'physics/raw':>12}",
        "{robot:6} {num_envs:5d} {env_steps_per_s:12d} {raw_steps_per_s:12d} {env_over_raw:8.2f}"
        " {physics_over_raw:12.2f}",
    )
    return results


if __name__ == "__main__":
    main()

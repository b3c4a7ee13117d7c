"""Batched teacher rollouts that keep N successful episodes, with every step's full sim state.

All envs step together; each env's episodes follow one another (the env resets an ended episode inside
`step`). Episodes are ranked by (round, env slot), where round counts the episodes an env has started, and the
first N successes in that order are kept. Keeping the first N to *end* instead would favour short episodes.
A snapshot of the whole batch is taken after every step; each env's running episode holds references to the
snapshots it spans, so memory stays bounded by the longest running episode.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from mobilemani_data.shards import FRAME_KEYS, Episode
from mobilemani_rl.envs.actions import dart_perturbed
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv

Policy = Callable[[], np.ndarray]


@dataclass
class Rollouts:
    episodes: list[Episode]
    attempts: int  # episodes that ended (kept or not)
    steps: int  # batch control steps run
    capped: bool  # stopped by max_steps before enough successes


def _snapshot(env: MobileManiEnv, success: np.ndarray, step: int) -> dict[str, np.ndarray | int]:
    """Copies of every env's state after a step (or reset);
    `action` is filled in when the next one is chosen."""
    frames = env.frames
    snap: dict[str, np.ndarray | int] = {k: getattr(frames, k).copy() for k in FRAME_KEYS}
    snap.update(state=env.batch.state.copy(), success=success.copy(), goal_pos=env.goal_pos.copy(), step=step)
    return snap


def _episode(snaps: list[dict], slot: int, round_: int) -> Episode:
    arrays = {k: np.stack([s[k][slot] for s in snaps]) for k in ("state", "action", "success", *FRAME_KEYS)}
    arrays["goal_pos"] = snaps[0]["goal_pos"][slot]
    return Episode(arrays, {"env_slot": slot, "round": round_, "start_step": snaps[0]["step"]})


def collect_successes(
    env: MobileManiEnv, policy: Policy, episodes: int, max_steps: int, seed: int, action_noise: float = 0.0
) -> Rollouts:
    """Step all envs until the first `episodes` successes in
    (round, slot) order are known, or `max_steps` ran.

    With `action_noise` > 0 the envs execute the teacher's action plus Gaussian noise of that standard
    deviation while the clean action is recorded (DART, `dart_perturbed`).
    """
    env.reset(seed=seed)
    noise_rng = np.random.default_rng(seed)
    n = env.num_envs
    snap = _snapshot(env, np.zeros(n, dtype=bool), 0)
    running: list[list[dict]] = [[snap] for _ in range(n)]
    rounds = [0] * n
    successes: dict[tuple[int, int], Episode] = {}
    attempts = steps = 0

    def decided() -> list[Episode]:
        """The first successes in rank order that no running episode can still precede."""
        first_open = min(zip(rounds, range(n), strict=True))
        return [successes[k] for k in sorted(successes) if k < first_open][:episodes]

    while len(decided()) < episodes and steps < max_steps:
        # The env clamps actions to [-1, 1] before IK; store them as applied, as the reference does.
        actions = np.clip(np.nan_to_num(np.asarray(policy(), dtype=np.float64), nan=0.0), -1.0, 1.0)
        snap["action"] = actions
        if action_noise > 0:
            actions = dart_perturbed(actions, action_noise, noise_rng)
        result = env.step(actions)
        steps += 1
        success = result.success_flag.copy()
        success[result.done_ids] = False  # those rows now hold a fresh episode's reset state
        snap = _snapshot(env, success, steps)
        done = set(result.done_ids.tolist())
        for slot in range(n):
            if slot not in done:
                running[slot].append(snap)
                continue
            attempts += 1
            # Kept only if a stored state is successful
            # (the terminal state is not stored).
            if running[slot][-1]["success"][slot]:
                successes[(rounds[slot], slot)] = _episode(running[slot], slot, rounds[slot])
            rounds[slot] += 1
            running[slot] = [snap]
    kept = decided()
    return Rollouts(kept, attempts, steps, capped=len(kept) < episodes)

"""The evaluation policy interface.

An observation is a dict keyed by the dataset's feature names (mobilemani_data.schema), each value batched
over the envs of one evaluation batch: images (n, H, W, 3) uint8, states (n, d) float32, plus `TASK`
(n instructions), `PRIVILEGED_STATE` (the RL observation, for teachers) and `ACTIVE` (n,) bool, the envs whose
first episode still runs. A policy names the keys it reads in `inputs`, so that the evaluator renders only the
cameras it needs, and returns chunks (n, N, action_dim) in `action_frame` ("world": the env's normalised
action; "base": the dataset's base-frame action). Rows of inactive envs are ignored;
model policies may skip computing them.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from mobilemani_rl.envs.mobilemani_env import MobileManiEnv

TASK = "task"
PRIVILEGED_STATE = "observation.privileged_state"
ACTIVE = "active"

ActionFrame = Literal["world", "base"]
Observation = dict[str, np.ndarray | list[str]]


class EvalPolicy:
    name: str = "policy"
    inputs: frozenset[str] = frozenset()
    action_frame: ActionFrame = "world"
    image_size: tuple[int, int] | None = (
        None  # (height, width) the policy's images were recorded at, if known
    )
    action_dim: int | None = None  # width of the actions it predicts, if fixed (a trained checkpoint's)
    chunk_length: int | None = None  # actions per predicted chunk, if known before the first prediction
    # How much training the policy holds (a trained checkpoint's steps, samples, episodes), recorded with its
    # results so that a table can state the scale of the run it reports
    training: dict | None = None

    def check_tasks(self, tasks: set[tuple[str, str, str]]) -> dict[str, str]:
        """Before anything runs or is written: stop with one error when a (robot, object, skill) task of the
        protocol cannot be evaluated (a privileged policy's missing teacher). Returns the checkpoint file each
        task's actions come from when the policy looks one up per task (teachers under a runs directory),
        'robot object skill' -> path; a fixed checkpoint is a setting already."""
        return {}

    def start(self, env: MobileManiEnv, seed: int) -> None:
        """A new batch of episodes starts in `env` (already reset with `seed`);
        privileged policies bind to it."""

    def act(self, obs: Observation) -> np.ndarray:
        raise NotImplementedError


def active_rows(obs: Observation) -> np.ndarray:
    return np.flatnonzero(obs[ACTIVE])


def scatter_rows(rows: np.ndarray, values: np.ndarray, n: int) -> np.ndarray:
    """Chunks computed for `rows` placed into a zero (n, N, A) array."""
    out = np.zeros((n, *values.shape[1:]), dtype=np.float64)
    out[rows] = values
    return out

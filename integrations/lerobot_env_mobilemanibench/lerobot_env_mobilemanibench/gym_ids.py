"""Gymnasium ids: `MobileManiBench/<robot>-v0` for each robot, one env (`gymnasium.make`) or a batched vector
on one MuJoCo batch (`gymnasium.make_vec(..., vectorization_mode="vector_entry_point")`)."""

from __future__ import annotations

import gymnasium as gym

from mobilemani_rl.assets.robots import ROBOTS

NAMESPACE = "MobileManiBench"
MODULE = "lerobot_env_mobilemanibench.vector_env"


def gym_id(robot: str) -> str:
    return f"{NAMESPACE}/{robot}-v0"


def register_gym_ids() -> None:
    for robot in ROBOTS:
        if gym_id(robot) not in gym.registry:
            gym.register(
                gym_id(robot),
                entry_point=f"{MODULE}:MobileManiBenchEnv",
                vector_entry_point=f"{MODULE}:make_vector_env",
                kwargs={"robot": robot},
                disable_env_checker=True,
            )

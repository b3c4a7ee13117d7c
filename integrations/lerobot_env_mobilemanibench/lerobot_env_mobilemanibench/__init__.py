"""MobileManiBench as a LeRobot env plugin (`lerobot-eval --env.type=mobilemanibench`) and as Gymnasium ids
(`gymnasium.make("MobileManiBench/g1-v0", object=..., skill=..., scene=...)`), both on the project's batched
env and its evaluation episodes."""

from lerobot_env_mobilemanibench.config import MobileManiBenchEnvConfig
from lerobot_env_mobilemanibench.gym_ids import register_gym_ids
from lerobot_env_mobilemanibench.vector_env import MobileManiBenchEnv, MobileManiBenchVectorEnv

# LeRobot imports the plugin to have it register itself: the config above did, the Gymnasium ids follow.
register_gym_ids()

__all__ = ["MobileManiBenchEnv", "MobileManiBenchEnvConfig", "MobileManiBenchVectorEnv", "register_gym_ids"]

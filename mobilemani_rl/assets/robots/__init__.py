"""Robot registry: name -> RobotDescription."""

from mobilemani_rl.assets.robots.description import RobotDescription
from mobilemani_rl.assets.robots.g1 import G1
from mobilemani_rl.assets.robots.xhand import XHAND
from mobilemani_rl.utils.errors import lookup

ROBOTS: dict[str, RobotDescription] = {"g1": G1, "xhand": XHAND}


def get_robot(name: str) -> RobotDescription:
    return lookup(ROBOTS, name, "robot")


__all__ = ["ROBOTS", "RobotDescription", "get_robot"]

"""What the environment needs to know about a robot, independent of how its model is built."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco

from mobilemani_rl.assets.robots.scripted_tuning import ScriptedPolicyCfg


@dataclass(frozen=True)
class RobotDescription:
    """Names and constants of one robot, with the same kinematic roles as the reference robots.

    The IK chain is base yaw + base forward slide + 7 arm joints, as in the reference; hand joints are
    mapped absolutely from [-1, 1] onto their limits, in action order. `hand_mimic` couples passive copies of
    a hand joint (the second finger of a parallel gripper) to their leader.
    """

    name: str
    build_spec: Callable[[], mujoco.MjSpec]
    ik_joints: tuple[str, ...]
    hand_joints: tuple[str, ...]
    hand_body: str
    palm_site: str
    finger_sites: tuple[str, ...]  # thumb (or outer finger) last, as the reference
    active_bodies: tuple[str, ...]
    base_body: str
    default_qpos: dict[str, float]
    grasp_hand_qpos: dict[str, float]  # hand joint targets of a closed grasp (used by the scripted policy)
    default_root_xy: tuple[float, float]
    head_camera: str
    wrist_camera: str
    scripted: ScriptedPolicyCfg  # the scripted policy's tuning for this robot
    hand_mimic: dict[str, str] = field(default_factory=dict)

    @property
    def base_joints(self) -> tuple[str, ...]:
        """The mobile base's joints: the IK chain's first two (yaw, then the slide along the heading)."""
        return self.ik_joints[:2]

    @property
    def action_dim(self) -> int:
        return 6 + len(self.hand_joints)

"""G1-like robot: rotating/sliding base, fixed torso, head and left arm, right 7-DoF arm, parallel gripper.

Frame conventions (robot root frame): forward +y, right +x, up +z, as the reference robot whose +y faces the
object. At zero joint angles the right arm hangs down; the default pose bends it so that the gripper points
forward at chest height with the fingers opening vertically (so a horizontal lid edge fits between them).
Joint and body names follow the reference G1 so that logs and data read the same.
"""

from __future__ import annotations

import math

import mujoco

from mobilemani_rl.assets.robots.builder import (
    BOX,
    CAPSULE,
    DARK_RGBA,
    PAD_FRICTION,
    SLIDE,
    add_arm,
    add_camera,
    add_geom,
    add_joint,
    add_link,
    add_mobile_base,
    add_position_actuator,
)
from mobilemani_rl.assets.robots.description import RobotDescription
from mobilemani_rl.scripted_config import ScriptedPolicyCfg

ARM_JOINTS = tuple(f"idx6{i}_arm_r_joint{i}" for i in range(1, 8))
GRIPPER_JOINT = "idx81_gripper_r_outer_joint1"
GRIPPER_MIMIC = "idx71_gripper_r_inner_joint1"

SHOULDER_HEIGHT = 0.8
UPPER_ARM, FOREARM = 0.30, 0.28
GRIPPER_REACH = 0.13  # gripper base -> fingertip centre (the palm point)
FINGER_TRAVEL = 0.04  # per finger; fully open gap = 8 cm
# Gripper frame at zero arm angles: approach (+z) = world -z, finger opening axis (+x) = world +y.
GRIPPER_QUAT = (0.0, math.sqrt(0.5), math.sqrt(0.5), 0.0)

DEFAULT_ARM = (0.5, 0.0, 0.0, math.pi / 2 - 0.5, 0.0, 0.0, 0.0)


def _build_gripper(spec: mujoco.MjSpec, wrist: mujoco.MjsBody) -> None:
    base = add_link(wrist, "gripper_r_base_link", (0, 0, -0.04), GRIPPER_QUAT)
    add_geom(base, BOX, (0.06, 0.025, 0.035), pos=(0, 0, 0.035), rgba=DARK_RGBA, mass=0.4)
    center = add_link(base, "gripper_r_center_link", (0, 0, GRIPPER_REACH))
    center.add_site(name="palm", size=[0.008, 0, 0], rgba=[1, 0, 0, 1], group=4)
    add_camera(base, "wrist_camera", pos=(0.0, -0.06, 0.02), forward=(0, 0, 1), up=(1, 0, 0))
    for side, name, joint in (
        (1, "gripper_r_outer_link5", GRIPPER_JOINT),
        (-1, "gripper_r_inner_link5", GRIPPER_MIMIC),
    ):
        finger = add_link(base, name, (0, 0, 0))
        # Positive joint values open the gripper: each finger slides outward along its side of the x axis.
        add_joint(finger, SLIDE, joint, (side, 0, 0), (0.0, FINGER_TRAVEL), armature=0.01, damping=20.0)
        add_geom(
            finger,
            BOX,
            (0.006, 0.018, 0.045),
            pos=(side * 0.008, 0, GRIPPER_REACH - 0.02),
            rgba=DARK_RGBA,
            mass=0.05,
            friction=PAD_FRICTION,
        )
        finger.add_site(name=f"{name}_tip", pos=[side * 0.008, 0, GRIPPER_REACH], size=[0.006, 0, 0], group=4)
        add_position_actuator(spec, joint, kp=200.0, kv=5.0, force=8.0, limits=(0.0, FINGER_TRAVEL))


def build_g1_spec() -> mujoco.MjSpec:
    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    spec.modelname = "g1"
    base = add_mobile_base(spec, "base_link", slide_limit=5.0)
    torso = add_link(base, "body_link1", (0, 0, 0.3))
    add_geom(torso, BOX, (0.09, 0.07, 0.2), pos=(0, 0, 0.2), collide=False, mass=5.0)
    chest = add_link(torso, "body_link2", (0, 0, 0.4))
    add_geom(chest, BOX, (0.16, 0.09, 0.16), pos=(0, 0, SHOULDER_HEIGHT - 0.7 - 0.04), mass=5.0)
    head = add_link(chest, "head_link2", (0, 0.02, SHOULDER_HEIGHT - 0.7 + 0.25))
    add_geom(head, BOX, (0.08, 0.08, 0.09), collide=False, rgba=DARK_RGBA, mass=1.0)
    # Head camera: forward along +y pitched 35° down (the reference's head pitch default is 0.6 rad).
    add_camera(
        head, "head_camera", pos=(0, 0.09, 0.0), forward=(0, math.cos(0.6), -math.sin(0.6)), up=(0, 0, 1)
    )
    arm_base = add_link(chest, "arm_base_link", (0, 0, SHOULDER_HEIGHT - 0.7))
    left = add_link(arm_base, "arm_l_base_link", (-0.2, 0, 0))  # left arm: fixed, hanging
    add_geom(
        left, CAPSULE, (0.045,), fromto=(0, 0, 0, 0, 0.05, -UPPER_ARM - FOREARM), collide=False, mass=2.0
    )
    shoulder = add_link(arm_base, "arm_r_base_link", (0.2, 0, 0))
    links = [f"arm_r_link{i}" for i in range(1, 7)] + ["arm_r_end_link"]
    wrist = add_arm(shoulder, links, ARM_JOINTS, [(-math.pi, math.pi)] * 7, (0, 1, 0), UPPER_ARM, FOREARM)
    _build_gripper(spec, wrist)
    for joint in ARM_JOINTS:
        add_position_actuator(spec, joint, kp=600.0, kv=30.0, force=300.0, limits=(-math.pi, math.pi))
    return spec


G1 = RobotDescription(
    name="g1",
    build_spec=build_g1_spec,
    ik_joints=("slider_basex", "slider_basey", *ARM_JOINTS),
    hand_joints=(GRIPPER_JOINT,),
    hand_mimic={GRIPPER_MIMIC: GRIPPER_JOINT},
    hand_body="gripper_r_center_link",
    palm_site="palm",
    finger_sites=("palm", "gripper_r_inner_link5_tip", "gripper_r_outer_link5_tip"),
    active_bodies=(
        "base_link",
        "body_link1",
        "body_link2",
        "arm_base_link",
        "arm_r_base_link",
        *(f"arm_r_link{i}" for i in range(1, 7)),
        "arm_r_end_link",
        "gripper_r_center_link",
        "gripper_r_inner_link5",
        "gripper_r_outer_link5",
    ),
    base_body="base_link",
    default_qpos={
        **dict(zip(ARM_JOINTS, DEFAULT_ARM, strict=True)),
        GRIPPER_JOINT: FINGER_TRAVEL,
        GRIPPER_MIMIC: FINGER_TRAVEL,
    },
    grasp_hand_qpos={GRIPPER_JOINT: 0.0},
    default_root_xy=(0.0, -1.5),
    head_camera="head_camera",
    wrist_camera="wrist_camera",
    # docs/results/scripted_success.md says why each value is what it is and what it measured
    scripted=ScriptedPolicyCfg(move_follow=0.0, approach_from_below=False),
)

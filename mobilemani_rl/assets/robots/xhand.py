"""XHand-like robot: the same mobile base and torso, an RM75-like 7-DoF right arm and a 12-DoF five-finger hand.

Hand frame (`xhand_right_base_link`): +z is the approach direction (the palm direction of the reference), the
palm faces -x, the fingers spread along y. Fingers curl toward the palm (-x) and the thumb leaves the palm face
and flexes toward the fingertips. Joint names, limits, defaults and action order are the reference's.
"""

from __future__ import annotations

import math

import mujoco

from mobilemani_rl.assets.robots.builder import (
    DARK_RGBA,
    add_arm,
    add_camera,
    add_geom,
    add_hinge,
    add_link,
    add_mobile_base,
    add_position_actuator,
)
from mobilemani_rl.assets.robots.description import RobotDescription
from mobilemani_rl.assets.robots.g1 import GRIPPER_QUAT, SHOULDER_HEIGHT

BOX = mujoco.mjtGeom.mjGEOM_BOX
CAPSULE = mujoco.mjtGeom.mjGEOM_CAPSULE

ARM_JOINTS = tuple(f"right_arm_joint{i}" for i in range(1, 8))
ARM_LIMITS = ((-3.107, 3.107), (-2.269, 2.269), (-3.107, 3.107), (-2.356, 2.356), (-3.107, 3.107),
              (-2.234, 2.234), (-6.283, 6.283))
UPPER_ARM, FOREARM = 0.30, 0.28
# Wrist pitch defaults to 0.5 rad (as the reference) so that the two forearm/hand roll axes stay apart.
DEFAULT_ARM = (0.8, 0.0, 0.0, math.pi / 2 - 1.3, 0.0, 0.5, 0.0)

P = "right_hand_"
HAND_LIMITS = {
    "index_bend": (-0.175, 0.175), "mid_joint1": (0.0, 1.92), "pinky_joint1": (0.0, 1.92),
    "ring_joint1": (0.0, 1.92), "thumb_bend": (0.0, 1.83), "index_joint1": (0.0, 1.92),
    "mid_joint2": (0.0, 1.94), "pinky_joint2": (0.0, 1.92), "ring_joint2": (0.0, 1.92),
    "thumb_rota_joint1": (-1.05, 1.57), "index_joint2": (0.0, 1.92), "thumb_rota_joint2": (-0.175, 1.83),
}
HAND_JOINTS = tuple(P + name for name in HAND_LIMITS)  # reference action order
# A wrapping grasp: fingers curl around a bar at the palm point, the thumb closes the cage from the wrist side.
HAND_GRASP = {"thumb_bend": 1.5, "thumb_rota_joint1": 0.8, "thumb_rota_joint2": 1.4, "index_bend": 0.0,
              "index_joint1": 1.6, "mid_joint1": 1.6, "ring_joint1": 1.6, "pinky_joint1": 1.6,
              "index_joint2": 1.9, "mid_joint2": 1.9, "ring_joint2": 1.9, "pinky_joint2": 1.9}
HAND_DEFAULT = {"thumb_bend": 1.5, "thumb_rota_joint1": 0.0, "thumb_rota_joint2": 0.5, "index_bend": 0.1,
                "index_joint1": 0.0, "mid_joint1": 0.0, "ring_joint1": 0.0, "pinky_joint1": 0.0,
                "index_joint2": 0.5, "mid_joint2": 0.5, "ring_joint2": 0.5, "pinky_joint2": 0.5}

PALM_LENGTH = 0.075  # knuckles just beyond the palm point, so curled fingers wrap a bar held there
PHALANX = (0.045, 0.035)
FINGER_Y = {"pinky": -0.033, "ring": -0.011, "mid": 0.011, "index": 0.033}
CURL_AXIS = (0, -1, 0)  # positive flexion turns +z toward the palm side (-x)
TIP_SITES = tuple(f"{P}{f}_tip" for f in ("pinky", "ring", "mid", "index", "thumb"))


def _add_phalanx(parent: mujoco.MjsBody, link: str, joint: str, pos, axis, length: float, direction) -> mujoco.MjsBody:
    body = add_link(parent, P + link, pos)
    add_hinge(body, P + joint, axis, HAND_LIMITS[joint], armature=0.002, damping=0.05)
    tip = [length * c for c in direction]
    add_geom(body, CAPSULE, (0.009,), fromto=(0, 0, 0, *tip), rgba=DARK_RGBA, mass=0.02,
             friction=(1.5, 0.01, 0.001))
    return body


def _build_hand(wrist: mujoco.MjsBody) -> None:
    cylinder = add_link(wrist, "Right_Cylinder_link", (0, 0, -0.02), GRIPPER_QUAT)
    add_geom(cylinder, mujoco.mjtGeom.mjGEOM_CYLINDER, (0.035, 0.02), pos=(0, 0, 0.02), rgba=DARK_RGBA, mass=0.2)
    add_camera(cylinder, "wrist_camera", pos=(0.0, -0.08, 0.02), forward=(0, 0, 1), up=(1, 0, 0))
    hand = add_link(cylinder, "xhand_right_base_link", (0, 0, 0.04))
    add_geom(hand, BOX, (0.015, 0.047, PALM_LENGTH / 2), pos=(0, 0, PALM_LENGTH / 2), mass=0.3)
    # Palm point: the reference offset (-0.04, 0, 0.06) in the hand frame, in front of the palm face.
    hand.add_site(name="palm", pos=[-0.04, 0, 0.06], size=[0.008, 0, 0], rgba=[1, 0, 0, 1], group=4)
    for finger, y in FINGER_Y.items():
        parent, first = hand, "joint1"
        base = (0, y, PALM_LENGTH)
        if finger == "index":
            parent = add_link(hand, P + "index_bend_link", base)
            add_hinge(parent, P + "index_bend", (1, 0, 0), HAND_LIMITS["index_bend"], armature=0.002, damping=0.05)
            add_geom(parent, mujoco.mjtGeom.mjGEOM_SPHERE, (0.01,), collide=False, mass=0.01)
            base = (0, 0, 0)
        link1 = "index_rota_link1" if finger == "index" else f"{finger}_link1"
        link2 = "index_rota_link2" if finger == "index" else f"{finger}_link2"
        proximal = _add_phalanx(parent, link1, f"{finger}_{first}", base, CURL_AXIS, PHALANX[0], (0, 0, 1))
        distal = _add_phalanx(proximal, link2, f"{finger}_joint2", (0, 0, PHALANX[0]), CURL_AXIS, PHALANX[1],
                              (0, 0, 1))
        distal.add_site(name=f"{P}{finger}_tip", pos=[-0.008, 0, PHALANX[1]], size=[0.006, 0, 0], group=4)
    # Thumb: points along +y at thumb_bend = 0, swings out of the palm face (-x) as thumb_bend grows.
    bend = add_link(hand, P + "thumb_bend_link", (-0.02, 0.03, 0.03))
    add_hinge(bend, P + "thumb_bend", (0, 0, 1), HAND_LIMITS["thumb_bend"], armature=0.002, damping=0.05)
    add_geom(bend, mujoco.mjtGeom.mjGEOM_SPHERE, (0.012,), collide=False, mass=0.01)
    rota1 = _add_phalanx(bend, "thumb_rota_link1", "thumb_rota_joint1", (0, 0.01, 0), (1, 0, 0), 0.04, (0, 1, 0))
    rota2 = _add_phalanx(rota1, "thumb_rota_link2", "thumb_rota_joint2", (0, 0.04, 0), (1, 0, 0), 0.035,
                         (0, 1, 0))
    rota2.add_site(name=f"{P}thumb_tip", pos=[0, 0.035, 0.006], size=[0.006, 0, 0], group=4)


def build_xhand_spec() -> mujoco.MjSpec:
    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    spec.modelname = "xhand"
    base = add_mobile_base(spec, "basey", slide_limit=5.0)
    add_camera(base, "head_camera", pos=(0, 0.1, 1.0), forward=(0, math.cos(math.pi / 6), -math.sin(math.pi / 6)),
               up=(0, 0, 1))
    torso = add_link(base, "torso_link", (0, 0, 0.3))
    add_geom(torso, BOX, (0.12, 0.09, 0.33), pos=(0, 0, 0.33), collide=False, mass=8.0)
    arm_base = add_link(base, "Right_Arm_base_link", (0.2, 0, SHOULDER_HEIGHT))
    add_geom(arm_base, mujoco.mjtGeom.mjGEOM_CYLINDER, (0.05, 0.04), collide=False, mass=0.5)
    left = add_link(base, "Left_Arm_base_link", (-0.2, 0, SHOULDER_HEIGHT))
    add_geom(left, CAPSULE, (0.045,), fromto=(0, 0, 0, 0, 0.05, -UPPER_ARM - FOREARM), collide=False, mass=2.0)
    links = [f"Right_Arm_Link{i}" for i in range(1, 8)]
    wrist = add_arm(arm_base, links, ARM_JOINTS, ARM_LIMITS, (0, 0, 1), UPPER_ARM, FOREARM)
    _build_hand(wrist)
    for joint, limits in zip(ARM_JOINTS, ARM_LIMITS, strict=True):
        add_position_actuator(spec, joint, kp=600.0, kv=30.0, force=300.0, limits=limits)
    for joint in HAND_JOINTS:
        # About 10 N at a fingertip: strong enough to hold handles, too weak to crush through thin parts.
        add_position_actuator(spec, joint, kp=0.5, kv=0.06, force=0.6, limits=HAND_LIMITS[joint.removeprefix(P)])
    return spec


HAND_LINKS = tuple(
    P + name for name in (
        "pinky_link1", "pinky_link2", "ring_link1", "ring_link2", "mid_link1", "mid_link2", "index_bend_link",
        "index_rota_link1", "index_rota_link2", "thumb_bend_link", "thumb_rota_link1", "thumb_rota_link2",
    )
)

XHAND = RobotDescription(
    name="xhand",
    build_spec=build_xhand_spec,
    ik_joints=("slider_basex", "slider_basey", *ARM_JOINTS),
    hand_joints=HAND_JOINTS,
    hand_body="xhand_right_base_link",
    palm_site="palm",
    finger_sites=TIP_SITES,
    active_bodies=("basey", "Right_Arm_base_link", *(f"Right_Arm_Link{i}" for i in range(1, 8)),
                   "xhand_right_base_link", *HAND_LINKS),
    base_body="basey",
    default_qpos={**dict(zip(ARM_JOINTS, DEFAULT_ARM, strict=True)),
                  **{P + name: value for name, value in HAND_DEFAULT.items()}},
    grasp_hand_qpos={P + name: value for name, value in HAND_GRASP.items()},
    default_root_xy=(0.0, -1.25),
    head_camera="head_camera",
    wrist_camera="wrist_camera",
)

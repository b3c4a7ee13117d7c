"""XHand-like robot: the same mobile base and torso,
an RM75-like 7-DoF right arm and a 12-DoF five-finger hand.

Hand frame (`xhand_right_base_link`, origin at the wrist on the back of the hand), as the reference XHand: +z
is the palm normal (the palm direction of the reference, and the approach direction), the fingers extend along
-x from the knuckles and spread along y, the index on the +y side. Fingers curl toward +z, so that closed
fingertips wrap over a bar held at the palm point (-0.04, 0, 0.06), 3 cm in front of the palm face. The thumb
sits beside the index: thumb_bend swings it in the palm plane from along the fingers (0) to sideways (+y, the
default), and its two rota joints raise it out of the palm and curl it over the palm point from the +y side.
Joint names, limits, defaults and action order are the reference's.
"""

from __future__ import annotations

import math

import mujoco

from mobilemani_rl.assets.collision import HAND_CONTACT
from mobilemani_rl.assets.robots.builder import (
    BOX,
    CAPSULE,
    DARK_RGBA,
    HINGE,
    PAD_FRICTION,
    add_arm,
    add_camera,
    add_geom,
    add_joint,
    add_link,
    add_mobile_base,
    add_position_actuator,
)
from mobilemani_rl.assets.robots.description import RobotDescription
from mobilemani_rl.assets.robots.scripted_tuning import ScriptedPolicyCfg

ARM_JOINTS = tuple(f"right_arm_joint{i}" for i in range(1, 8))
ARM_LIMITS = (
    (-3.107, 3.107),
    (-2.269, 2.269),
    (-3.107, 3.107),
    (-2.356, 2.356),
    (-3.107, 3.107),
    (-2.234, 2.234),
    (-6.283, 6.283),
)
UPPER_ARM, FOREARM = 0.30, 0.28
SHOULDER_HEIGHT = 0.8
# Hand adapter frame at zero arm angles: approach (+z) = world -z, opening/wrist axis (+x) = world +y.
GRIPPER_QUAT = (0.0, math.sqrt(0.5), math.sqrt(0.5), 0.0)
# Forearm pointing forward and slightly down, wrist flexed so that the fingers hang down and the palm faces
# forward (+y) at (0.2, 0.55, 0.45) in the base frame. The wrist pitch stays far from 0, where the forearm and
# hand roll axes align.
DEFAULT_ARM = (0.853, 0.0, 0.0, 0.637, 0.0, -1.49, 0.0)

P = "right_hand_"
PALM_LINK = "xhand_right_base_link"
HAND_LIMITS = {
    "index_bend": (-0.175, 0.175),
    "mid_joint1": (0.0, 1.92),
    "pinky_joint1": (0.0, 1.92),
    "ring_joint1": (0.0, 1.92),
    "thumb_bend": (0.0, 1.83),
    "index_joint1": (0.0, 1.92),
    "mid_joint2": (0.0, 1.94),
    "pinky_joint2": (0.0, 1.92),
    "ring_joint2": (0.0, 1.92),
    "thumb_rota_joint1": (-1.05, 1.57),
    "index_joint2": (0.0, 1.92),
    "thumb_rota_joint2": (-0.175, 1.83),
}
HAND_JOINTS = tuple(P + name for name in HAND_LIMITS)  # reference action order
# A caging grasp of a bar at the palm point: the four fingers curl over its far side, the thumb stands up
# beside the wrist and its distal phalanx crosses over the palm.
HAND_GRASP = {
    "thumb_bend": 1.5,
    "thumb_rota_joint1": 1.5,
    "thumb_rota_joint2": 1.6,
    "index_bend": 0.0,
    "index_joint1": 1.6,
    "mid_joint1": 1.6,
    "ring_joint1": 1.6,
    "pinky_joint1": 1.6,
    "index_joint2": 1.7,
    "mid_joint2": 1.7,
    "ring_joint2": 1.7,
    "pinky_joint2": 1.7,
}
HAND_DEFAULT = {
    "thumb_bend": 1.5,
    "thumb_rota_joint1": 0.0,
    "thumb_rota_joint2": 0.5,
    "index_bend": 0.1,
    "index_joint1": 0.0,
    "mid_joint1": 0.0,
    "ring_joint1": 0.0,
    "pinky_joint1": 0.0,
    "index_joint2": 0.5,
    "mid_joint2": 0.5,
    "ring_joint2": 0.5,
    "pinky_joint2": 0.5,
}

PALM = (0.09, 0.09, 0.03)  # length (x), width (y), thickness (z): the palm face is at z = 0.03
WRIST_X = 0.03  # the palm spans x in [WRIST_X - 0.09, WRIST_X]
# Knuckles 2.5 cm past the palm point along -x, as a bar held at the base of the fingers: the proximal
# phalanges clear a 1.3 cm bar there and reach 2 cm beyond the palm point along +z, so that the curled distal
# phalanges lie over the bar's far side (a hook), yet short of a surface 3.5 cm behind the bar.
KNUCKLE = (-0.065, 0.024)  # x, z of the finger base joints
PHALANX = (0.056, 0.038)
FINGER_Y = {"pinky": -0.033, "ring": -0.011, "mid": 0.011, "index": 0.033}
# The thumb rises next to the wrist, on the +x side of a bar at the palm point, and its distal phalanx closes
# the cage there: a bar pulled toward the wrist cannot slip out of the finger hooks.
THUMB_BASE = (-0.008, 0.05, 0.02)
THUMB_PHALANX = (0.045, 0.035)
CURL_AXIS = (0, 1, 0)  # positive flexion turns a digit pointing along -x toward +z (out of the palm)
# Hand link in the flange adapter (whose +z continues the forearm): fingers (-x) along the forearm, palm
# normal (+z) along the adapter's +x, so that the wrist pitch turns the palm forward; the adapter axis runs
# through the middle of the palm's thickness.
HAND_QUAT = (math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0)
TIP_SITES = tuple(f"{P}{f}_tip" for f in ("pinky", "ring", "mid", "index", "thumb"))


def _add_hand_hinge(body: mujoco.MjsBody, joint: str, axis: tuple[float, float, float]) -> None:
    add_joint(body, HINGE, P + joint, axis, HAND_LIMITS[joint], armature=0.002, damping=0.05)


def _add_phalanx(parent: mujoco.MjsBody, link: str, joint: str, pos, length: float) -> mujoco.MjsBody:
    """A link pointing along its local -x, flexing about local +y."""
    body = add_link(parent, P + link, pos)
    _add_hand_hinge(body, joint, CURL_AXIS)
    add_geom(
        body,
        CAPSULE,
        (0.009,),
        fromto=(0, 0, 0, -length, 0, 0),
        rgba=DARK_RGBA,
        contact=HAND_CONTACT,
        mass=0.02,
        friction=PAD_FRICTION,
    )
    return body


def _add_digit(
    parent: mujoco.MjsBody,
    name: str,
    links: tuple[str, str],
    joints: tuple[str, str],
    pos,
    lengths: tuple[float, float],
) -> None:
    proximal = _add_phalanx(parent, links[0], joints[0], pos, lengths[0])
    distal = _add_phalanx(proximal, links[1], joints[1], (-lengths[0], 0, 0), lengths[1])
    # Tip point on the pad (+z side) near the end of the distal phalanx.
    distal.add_site(name=f"{P}{name}_tip", pos=[-lengths[1] + 0.004, 0, 0.006], size=[0.006, 0, 0], group=4)


def _build_hand(wrist: mujoco.MjsBody) -> None:
    adapter = add_link(wrist, "Right_Cylinder_link", (0, 0, -0.02), GRIPPER_QUAT)
    add_geom(
        adapter, mujoco.mjtGeom.mjGEOM_CYLINDER, (0.035, 0.02), pos=(0, 0, 0.02), rgba=DARK_RGBA, mass=0.2
    )
    length, width, thickness = PALM
    hand = add_link(adapter, PALM_LINK, (-thickness / 2, 0, 0.04 + WRIST_X), HAND_QUAT)
    add_geom(
        hand,
        BOX,
        (length / 2, width / 2, thickness / 2),
        pos=(WRIST_X - length / 2, 0, thickness / 2),
        contact=HAND_CONTACT,
        mass=0.3,
    )
    # Palm point: the reference offset (-0.04, 0, 0.06) in the hand frame, in front of the palm face.
    hand.add_site(name="palm", pos=[-0.04, 0, 0.06], size=[0.008, 0, 0], rgba=[1, 0, 0, 1], group=4)
    # Wrist camera above the back of the wrist, looking out of the palm and slightly along the fingers.
    add_camera(hand, "wrist_camera", pos=(WRIST_X + 0.01, 0.0, 0.05), forward=(-0.35, 0, 1), up=(-1, 0, 0))
    for finger, y in FINGER_Y.items():
        parent, base = hand, (KNUCKLE[0], y, KNUCKLE[1])
        if finger == "index":
            # Abduction about the palm normal, then the flexion chain.
            parent = add_link(hand, P + "index_bend_link", base)
            _add_hand_hinge(parent, "index_bend", (0, 0, 1))
            add_geom(parent, mujoco.mjtGeom.mjGEOM_SPHERE, (0.01,), collide=False, mass=0.01)
            base = (0, 0, 0)
        links = (
            ("index_rota_link1", "index_rota_link2")
            if finger == "index"
            else (f"{finger}_link1", f"{finger}_link2")
        )
        _add_digit(parent, finger, links, (f"{finger}_joint1", f"{finger}_joint2"), base, PHALANX)
    # Thumb: thumb_bend swings it about the palm normal from along the fingers (-x, at 0) to sideways (+y).
    bend = add_link(hand, P + "thumb_bend_link", THUMB_BASE)
    _add_hand_hinge(bend, "thumb_bend", (0, 0, -1))
    add_geom(bend, mujoco.mjtGeom.mjGEOM_SPHERE, (0.012,), collide=False, mass=0.01)
    _add_digit(
        bend,
        "thumb",
        ("thumb_rota_link1", "thumb_rota_link2"),
        ("thumb_rota_joint1", "thumb_rota_joint2"),
        (0, 0, 0),
        THUMB_PHALANX,
    )


def build_xhand_spec() -> mujoco.MjSpec:
    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    spec.modelname = "xhand"
    base = add_mobile_base(spec, "basey", slide_limit=5.0)
    add_camera(
        base,
        "head_camera",
        pos=(0, 0.1, 1.0),
        forward=(0, math.cos(math.pi / 6), -math.sin(math.pi / 6)),
        up=(0, 0, 1),
    )
    torso = add_link(base, "torso_link", (0, 0, 0.3))
    add_geom(torso, BOX, (0.12, 0.09, 0.33), pos=(0, 0, 0.33), collide=False, mass=8.0)
    arm_base = add_link(base, "Right_Arm_base_link", (0.2, 0, SHOULDER_HEIGHT))
    add_geom(arm_base, mujoco.mjtGeom.mjGEOM_CYLINDER, (0.05, 0.04), collide=False, mass=0.5)
    left = add_link(base, "Left_Arm_base_link", (-0.2, 0, SHOULDER_HEIGHT))
    add_geom(
        left, CAPSULE, (0.045,), fromto=(0, 0, 0, 0, 0.05, -UPPER_ARM - FOREARM), collide=False, mass=2.0
    )
    links = [f"Right_Arm_Link{i}" for i in range(1, 8)]
    wrist = add_arm(arm_base, links, ARM_JOINTS, ARM_LIMITS, (0, 0, 1), UPPER_ARM, FOREARM)
    _build_hand(wrist)
    # The index and thumb root in the palm through their abduction links, so MuJoCo's parent-child filter
    # misses the knuckle contact between their proximal phalanx and the palm (always touching: a knuckle).
    for digit in ("index", "thumb"):
        spec.add_exclude(bodyname1=PALM_LINK, bodyname2=f"{P}{digit}_rota_link1")
    for joint, limits in zip(ARM_JOINTS, ARM_LIMITS, strict=True):
        add_position_actuator(spec, joint, kp=600.0, kv=30.0, force=300.0, limits=limits)
    for joint in HAND_JOINTS:
        # About 10 N at a fingertip: strong enough to hold handles, too weak to crush through thin parts.
        add_position_actuator(
            spec, joint, kp=0.5, kv=0.06, force=0.6, limits=HAND_LIMITS[joint.removeprefix(P)]
        )
    return spec


HAND_LINKS = tuple(
    P + name
    for name in (
        "pinky_link1",
        "pinky_link2",
        "ring_link1",
        "ring_link2",
        "mid_link1",
        "mid_link2",
        "index_bend_link",
        "index_rota_link1",
        "index_rota_link2",
        "thumb_bend_link",
        "thumb_rota_link1",
        "thumb_rota_link2",
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
    active_bodies=(
        "basey",
        "Right_Arm_base_link",
        *(f"Right_Arm_Link{i}" for i in range(1, 8)),
        "xhand_right_base_link",
        *HAND_LINKS,
    ),
    base_body="basey",
    default_qpos={
        **dict(zip(ARM_JOINTS, DEFAULT_ARM, strict=True)),
        **{P + name: value for name, value in HAND_DEFAULT.items()},
    },
    grasp_hand_qpos={P + name: value for name, value in HAND_GRASP.items()},
    default_root_xy=(0.0, -1.25),
    head_camera="head_camera",
    wrist_camera="wrist_camera",
    # docs/results/fidelity.md says why each value is what it is and what it measured
    scripted=ScriptedPolicyCfg(
        grasp_depth=0.012,
        close_steps=15,
        grip_shift=0.02,
        lid_grip_shift=-0.02,
        pick_finger_yaw=0.9,
        pick_grip_shift=0.043,
        pick_descent_while_moving=0.1,
        push_lids_shut=True,
        hooked_lips=("laptop",),
        lip_hook_shift=0.08,
    ),
)

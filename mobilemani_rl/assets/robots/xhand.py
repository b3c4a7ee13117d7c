"""XHand-like robot: the same mobile base and torso, an RM75-like 7-DoF right arm and RobotEra's 12-DoF
five-finger XHAND1 hand.

The hand follows the vendored RobotEra URDF (third_party/robotera_xhand/l3_with_hand_fixedpin_xml.urdf,
BSD-3-Clause: the STAR1 humanoid with two XHAND1 hands): each right-hand joint's origin (position and
orientation in its parent link), axis and limits, each link's inertial, and the phalanx lengths (the origins
of the next joint and of the URDF's fixed fingertip frames). Collision shapes stay primitive (the URDF's
meshes are not vendored): a capsule down each phalanx and a box for the palm.

Hand frame (`xhand_right_base_link`, origin at the wrist on the forearm axis), as the reference XHand: +z is
the palm normal (the palm direction of the reference, and the approach direction), the fingers extend along
-x from the knuckles and spread along y, the index on the +y side; the palm point is the reference's offset
(-0.04, 0, 0.06), 3.5 cm in front of the palm face. The URDF's hand link (right_hand_link) has the fingers
along -z, the palm normal +y and the index at +x, so one fixed rotation (URDF_TO_HAND, +120° about (1, 1, 1))
maps it onto this frame at the mount; every finger link below keeps the URDF's own frame (the reference's
fingertip offsets are in those frames). Fingers curl toward +z. The thumb's base sits near the wrist on the
index side: thumb_bend turns it about the hand's long axis from sideways in the palm plane (+y, at 0) to
standing out of the palm (+z, near the default 1.5), and its two rota joints curl it toward the fingertips.
Joint names, defaults and action order are the reference's; the limits are the URDF's (the reference's
mid_joint2 reaches 1.94, the URDF's 1.92).
"""

from __future__ import annotations

import math
from functools import cache

import mujoco
import numpy as np

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
from mobilemani_rl.assets.robots.urdf import (
    XHAND_URDF,
    Urdf,
    UrdfJoint,
    add_urdf_link,
    load_urdf,
    rotate,
    set_urdf_inertial,
)

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
URDF_HAND_LINK = "right_hand_link"
# The reference's hand joints in its action order. The URDF names the two abduction joints *_bend_joint.
HAND_JOINT_NAMES = (
    "index_bend",
    "mid_joint1",
    "pinky_joint1",
    "ring_joint1",
    "thumb_bend",
    "index_joint1",
    "mid_joint2",
    "pinky_joint2",
    "ring_joint2",
    "thumb_rota_joint1",
    "index_joint2",
    "thumb_rota_joint2",
)
HAND_JOINTS = tuple(P + name for name in HAND_JOINT_NAMES)  # reference action order
URDF_JOINT = {P + name: P + name + ("_joint" if name.endswith("_bend") else "") for name in HAND_JOINT_NAMES}
# A hook grasp of a bar in front of the palm, 4.5 cm from the palm point toward the knuckles: the four fingers
# curl over its far side (their distal phalanges come back over it, about 3 cm above the palm face). The
# thumb, turned 30° out of the palm plane, curls beside the index, clear of the cage (thumb and index share
# the +y side of the palm). Standing further out it fails the cart pulls, flat the refrigerators' vertical
# bars (docs/results/fidelity.md). The scripted policy picks with the thumb standing
# (ScriptedPolicyCfg.pick_hand).
HAND_GRASP = {
    "thumb_bend": 0.5,
    "thumb_rota_joint1": 0.5,
    "thumb_rota_joint2": 1.0,
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

# URDF hand link -> hand frame: fingers -z -> -x, palm normal +y -> +z, index side +x -> +y (a cyclic
# permutation of the axes: +120° about (1, 1, 1)).
URDF_TO_HAND = (0.5, 0.5, 0.5, 0.5)
# Palm box: the extent of the upstream palm mesh (star1/meshes/right_hand_link.STL, not vendored) in the
# URDF hand link's frame, (min, max) per axis: 9.4 cm wide (x), 5 cm thick (y, centred on the forearm axis),
# 11.8 cm from the wrist to past the knuckles (z).
PALM_EXTENT_URDF = ((-0.0502, -0.025, -0.118), (0.0437, 0.025, 0.0))
PHALANX_RADIUS = 0.009  # about half the width of the URDF's finger meshes (1.6-1.7 cm)
# Fingertip points in the distal links' own (URDF) frames, as the reference: 3 cm down the finger on the pad.
FINGER_TIP = (0.0, 0.01, -0.03)
THUMB_TIP = (0.03, 0.0, -0.01)
# Hand link in the flange adapter (whose +z continues the forearm): fingers (-x) along the forearm, palm
# normal (+z) along the adapter's +x, so that the wrist pitch turns the palm forward; the hand's wrist (the
# URDF hand link's origin, on the forearm axis) at the adapter's end.
HAND_QUAT = (math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0)
ADAPTER_LENGTH = 0.04
DIGITS = ("pinky", "ring", "mid", "index", "thumb")
TIP_SITES = tuple(f"{P}{f}_tip" for f in DIGITS)


@cache
def xhand_urdf() -> Urdf:
    return load_urdf(XHAND_URDF)


def hand_limits() -> dict[str, tuple[float, float]]:
    """Each hand joint's limits (our joint name -> (lower, upper)), from the URDF."""
    joints = xhand_urdf().joints
    return {name: joints[URDF_JOINT[name]].limits for name in HAND_JOINTS}


def digit_chain(urdf: Urdf, digit: str) -> list[UrdfJoint]:
    """The digit's URDF joints from the hand link out: its revolute joints, then the fixed fingertip frame."""
    (joint,) = [
        j
        for j in urdf.joints.values()
        if j.parent == URDF_HAND_LINK and j.child.startswith(f"{P}{digit}_") and j.type == "revolute"
    ]
    chain = [joint]
    while chain[-1].type != "fixed":
        (joint,) = [j for j in urdf.joints.values() if j.parent == chain[-1].child]
        chain.append(joint)
    return chain


def _build_hand(wrist: mujoco.MjsBody) -> None:
    urdf = xhand_urdf()
    ours = {urdf_name: name for name, urdf_name in URDF_JOINT.items()}
    adapter = add_link(wrist, "Right_Cylinder_link", (0, 0, -0.02), GRIPPER_QUAT)
    add_geom(
        adapter,
        mujoco.mjtGeom.mjGEOM_CYLINDER,
        (0.035, ADAPTER_LENGTH / 2),
        pos=(0, 0, ADAPTER_LENGTH / 2),
        rgba=DARK_RGBA,
        mass=0.2,
    )
    hand = add_link(adapter, PALM_LINK, (0, 0, ADAPTER_LENGTH), HAND_QUAT)
    set_urdf_inertial(hand, urdf.inertials[URDF_HAND_LINK], quat=URDF_TO_HAND)
    low, high = (rotate(URDF_TO_HAND, v) for v in np.asarray(PALM_EXTENT_URDF, float))
    low, high = np.minimum(low, high), np.maximum(low, high)
    add_geom(hand, BOX, (high - low) / 2, pos=(high + low) / 2, contact=HAND_CONTACT)
    # Palm point: the reference offset (-0.04, 0, 0.06) in the hand frame, in front of the palm face.
    hand.add_site(name="palm", pos=[-0.04, 0, 0.06], size=[0.008, 0, 0], rgba=[1, 0, 0, 1], group=4)
    # Wrist camera 2 cm above the palm face at the wrist, looking out of the palm, a little along the fingers.
    face = high[2]
    add_camera(hand, "wrist_camera", pos=(0.01, 0.0, face + 0.02), forward=(-0.35, 0, 1), up=(-1, 0, 0))
    for digit in DIGITS:
        chain = digit_chain(urdf, digit)
        parent, quat = hand, URDF_TO_HAND
        for i, joint in enumerate(chain[:-1]):
            body = add_urdf_link(parent, urdf, joint, quat=quat)
            name = ours[joint.name]
            add_joint(body, HINGE, name, joint.axis, joint.limits, armature=0.002, damping=0.05)
            length = np.asarray(chain[i + 1].xyz, float)  # the next joint, or the fingertip frame
            if i < len(chain) - 3:  # an abduction link (index_bend, thumb_bend) inside the palm
                add_geom(body, mujoco.mjtGeom.mjGEOM_SPHERE, (0.01,), collide=False)
            else:  # a phalanx: a capsule from its joint to the next
                add_geom(
                    body,
                    CAPSULE,
                    (PHALANX_RADIUS,),
                    fromto=(0, 0, 0, *length),
                    rgba=DARK_RGBA,
                    contact=HAND_CONTACT,
                    friction=PAD_FRICTION,
                )
            parent, quat = body, None
        tip = THUMB_TIP if digit == "thumb" else FINGER_TIP
        parent.add_site(name=f"{P}{digit}_tip", pos=list(tip), size=[0.006, 0, 0], group=4)


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
    for joint, limits in hand_limits().items():
        # About 10 N at a fingertip: strong enough to hold handles, too weak to crush through thin parts.
        add_position_actuator(spec, joint, kp=0.5, kv=0.06, force=0.6, limits=limits)
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
        grip_shift=0.05,
        open_hand={P + "thumb_bend": 0.0},
        pick_hand={P + "thumb_bend": 1.5, P + "thumb_rota_joint1": 0.0, P + "thumb_rota_joint2": 1.0},
        pick_finger_yaw=0.9,
        pick_grip_shift=0.12,
        pick_grasp_depth=0.022,
        pick_descent_while_moving=0.1,
        push_lids_shut=True,
        hooked_lips=("laptop",),
        lip_hook_shift=0.115,
        lip_hook_depth=0.022,
        regrasp_distance=0.08,
    ),
)

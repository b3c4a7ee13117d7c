"""Small MjSpec helpers shared by the robot models: links, joints, PD actuators, collision classes."""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from mobilemani_rl.assets.collision import ROBOT_CONTACT
from mobilemani_rl.utils.rotations import quat_from_matrix

BOX, CAPSULE = mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_CAPSULE
HINGE, SLIDE = mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE
ROBOT_RGBA = (0.85, 0.85, 0.88, 1.0)
DARK_RGBA = (0.2, 0.2, 0.22, 1.0)
FINGER_SOLIMP = (0.99, 0.995, 0.001, 0.5, 2.0)
# Sliding friction of the gripper pads and XHand phalanges. The reference's 1.0 (times the object's 1.0) would
# be 1.0 here too (MuJoCo takes a pair's larger value), but MuJoCo's soft contacts let held objects slip and
# the scripted G1 pick loses episodes (docs/results/fidelity.md).
PAD_FRICTION = (1.5, 0.01, 0.001)
BASE_RADIUS = 0.26  # m, the mobile base's collision cylinder


def add_geom(
    body: mujoco.MjsBody,
    kind: mujoco.mjtGeom,
    size: Sequence[float],
    *,
    pos: Sequence[float] = (0, 0, 0),
    quat: Sequence[float] = (1, 0, 0, 0),
    fromto: Sequence[float] | None = None,
    rgba: Sequence[float] = ROBOT_RGBA,
    collide: bool = True,
    contact: tuple[int, int] = ROBOT_CONTACT,
    mass: float | None = None,
    friction: Sequence[float] | None = None,
) -> mujoco.MjsGeom:
    """Add a robot geom; collidable ones touch the world (objects, stage) and, with HAND_CONTACT, each other
    (mobilemani_rl.assets.collision)."""
    geom = body.add_geom(type=kind, size=list(size) + [0] * (3 - len(size)), rgba=list(rgba))
    if fromto is not None:
        geom.fromto = list(fromto)
    else:
        geom.pos = list(pos)
        geom.quat = list(quat)
    geom.contype, geom.conaffinity = contact if collide else (0, 0)
    if mass is not None:
        geom.mass = mass
    if friction is not None:
        geom.friction = list(friction)
    if collide:
        # Near-hard contacts: with the default impedance (0.9) a light held object (10 g) sinks centimetres
        # into the fingers, since MuJoCo's soft-contact penetration scales with the inverse effective mass.
        # A large solmix makes these parameters win over the object's when MuJoCo mixes the pair's.
        geom.solimp = list(FINGER_SOLIMP)
        geom.solmix = 100.0
    return geom


def add_link(
    parent: mujoco.MjsBody,
    name: str,
    pos: Sequence[float],
    quat: Sequence[float] = (1, 0, 0, 0),
) -> mujoco.MjsBody:
    """A robot body; gravity compensation stands in for the reference's disabled robot gravity."""
    body = parent.add_body(name=name, pos=list(pos), quat=list(quat))
    body.gravcomp = 1.0
    return body


def add_joint(
    body: mujoco.MjsBody,
    kind: mujoco.mjtJoint,
    name: str,
    axis: Sequence[float],
    limits: tuple[float, float],
    *,
    armature: float,
    damping: float,
) -> mujoco.MjsJoint:
    """A limited hinge or slide joint."""
    return body.add_joint(
        name=name,
        type=kind,
        axis=list(axis),
        range=list(limits),
        limited=mujoco.mjtLimited.mjLIMITED_TRUE,
        armature=armature,
        damping=damping,
    )


def add_position_actuator(
    spec: mujoco.MjSpec, joint: str, kp: float, kv: float, force: float, limits: tuple[float, float]
) -> mujoco.MjsActuator:
    """A PD position servo named after its joint, with ctrl in joint units clamped to the joint limits."""
    act = spec.add_actuator(name=joint, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
    act.set_to_position(kp=kp, kv=kv)
    act.ctrlrange = list(limits)
    act.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
    act.forcerange = [-force, force]
    act.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    return act


def add_camera(
    body: mujoco.MjsBody,
    name: str,
    pos: Sequence[float],
    forward: Sequence[float],
    up: Sequence[float],
    fovy: float = 90.0,
) -> mujoco.MjsCamera:
    """A camera looking along `forward` with `up` on top (MuJoCo cameras look down their -z axis)."""
    forward = np.asarray(forward, float) / np.linalg.norm(forward)
    up = np.asarray(up, float)
    up = up - forward * (up @ forward)
    up /= np.linalg.norm(up)
    right = np.cross(forward, up)
    quat = quat_from_matrix(np.stack((right, up, -forward), axis=1))
    return body.add_camera(name=name, pos=list(pos), quat=list(quat), fovy=fovy)


# Axes of the shared 7-DoF layout at zero angles (arm hanging down): shoulder pitch, shoulder roll, upper-arm
# twist, elbow pitch, forearm twist, wrist pitch, and a last wrist joint whose axis each robot chooses.
ARM_AXES = ((1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 0, 0), (0, 0, 1), (1, 0, 0))


def add_arm(
    shoulder: mujoco.MjsBody,
    links: Sequence[str],
    joints: Sequence[str],
    limits: Sequence[tuple[float, float]],
    last_axis: Sequence[float],
    upper_arm: float,
    forearm: float,
) -> mujoco.MjsBody:
    """Seven links in series from the shoulder; returns the last link (the wrist flange)."""
    axes = (*ARM_AXES, tuple(last_axis))
    offsets = ((0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, -upper_arm), (0, 0, 0), (0, 0, -forearm), (0, 0, 0))
    parent = shoulder
    for index, (name, joint, axis, offset, limit) in enumerate(
        zip(links, joints, axes, offsets, limits, strict=True)
    ):
        link = add_link(parent, name, offset)
        add_joint(link, HINGE, joint, axis, limit, armature=0.05, damping=1.0)
        if index in (2, 4):  # upper arm and forearm: a capsule down the segment
            radius, length, mass = (0.045, upper_arm, 1.5) if index == 2 else (0.04, forearm, 1.2)
            add_geom(link, CAPSULE, (radius,), fromto=(0, 0, -0.03, 0, 0, -length + 0.03), mass=mass)
        elif index == 6:
            add_geom(
                link,
                mujoco.mjtGeom.mjGEOM_CYLINDER,
                (0.04, 0.02),
                pos=(0, 0, -0.02),
                rgba=DARK_RGBA,
                mass=0.3,
            )
        else:
            add_geom(link, mujoco.mjtGeom.mjGEOM_SPHERE, (0.05,), collide=False, mass=0.5)
        parent = link
    return parent


def add_mobile_base(spec: mujoco.MjSpec, base_name: str, slide_limit: float) -> mujoco.MjsBody:
    """Mocap root (placed per env at reset) -> yaw hinge `slider_basex` -> forward slide `slider_basey`.

    As the reference's rotate-base robots: rotate about the root point, then translate along the heading.
    """
    root = spec.worldbody.add_body(name="Root", mocap=True)
    yaw = add_link(root, "basex", (0, 0, 0))
    add_joint(yaw, HINGE, "slider_basex", (0, 0, 1), (-np.pi, np.pi), armature=1.0, damping=5.0)
    add_geom(
        yaw,
        mujoco.mjtGeom.mjGEOM_CYLINDER,
        (0.1, 0.01),
        pos=(0, 0, 0.02),
        collide=False,
        rgba=DARK_RGBA,
        mass=1.0,
    )
    base = add_link(yaw, base_name, (0, 0, 0))
    add_joint(base, SLIDE, "slider_basey", (0, 1, 0), (-slide_limit, slide_limit), armature=1.0, damping=5.0)
    add_geom(
        base, mujoco.mjtGeom.mjGEOM_CYLINDER, (BASE_RADIUS, 0.12), pos=(0, 0, 0.15), rgba=DARK_RGBA, mass=20.0
    )
    add_position_actuator(spec, "slider_basex", kp=3000.0, kv=400.0, force=2000.0, limits=(-np.pi, np.pi))
    add_position_actuator(
        spec, "slider_basey", kp=8000.0, kv=800.0, force=4000.0, limits=(-slide_limit, slide_limit)
    )
    return base

"""MjSpec helpers for object generators: world-contact geoms, hinged/sliding links, the grasp site."""

from __future__ import annotations

from collections.abc import Sequence

import mujoco

from mobilemani_rl.assets.collision import WORLD_CONTACT
from mobilemani_rl.assets.objects.categories import CategoryParams
from mobilemani_rl.assets.objects.model import GRASP_SITE, ROOT_BODY

BOX = mujoco.mjtGeom.mjGEOM_BOX
CAPSULE = mujoco.mjtGeom.mjGEOM_CAPSULE
CYLINDER = mujoco.mjtGeom.mjGEOM_CYLINDER

# Passive object joints: no stiffness, damping 0.1, as in the reference.
JOINT_DAMPING = 0.1


def new_object_spec(name: str) -> tuple[mujoco.MjSpec, mujoco.MjsBody]:
    spec = mujoco.MjSpec()
    spec.modelname = name
    spec.compiler.degree = False
    return spec, spec.worldbody.add_body(name=ROOT_BODY)


def add_part(
    body: mujoco.MjsBody,
    kind: mujoco.mjtGeom,
    size: Sequence[float],
    rgba: Sequence[float],
    *,
    pos: Sequence[float] = (0, 0, 0),
    fromto: Sequence[float] | None = None,
    mass: float | None = None,
    density: float = 300.0,
) -> mujoco.MjsGeom:
    """A geom that touches the robot and the world; give `mass` on operated links (category mass)."""
    geom = body.add_geom(type=kind, size=list(size) + [0] * (3 - len(size)), rgba=list(rgba), density=density)
    if mass is not None:
        geom.mass = mass
    if fromto is not None:
        geom.fromto = list(fromto)
    else:
        geom.pos = list(pos)
    geom.contype, geom.conaffinity = WORLD_CONTACT
    return geom


def add_moving_link(
    parent: mujoco.MjsBody,
    name: str,
    pos: Sequence[float],
    *,
    joint: str,
    joint_type: mujoco.mjtJoint,
    axis: Sequence[float],
    limits: tuple[float, float],
) -> mujoco.MjsBody:
    """The operated link with its passive joint."""
    link = parent.add_body(name=name, pos=list(pos))
    link.add_joint(
        name=joint,
        type=joint_type,
        axis=list(axis),
        range=list(limits),
        limited=mujoco.mjtLimited.mjLIMITED_TRUE,
        damping=JOINT_DAMPING,
    )
    return link


def apply_gravity_setting(spec: mujoco.MjSpec, params: CategoryParams) -> None:
    """Categories without gravity (all but carts and rigid objects) get full gravity compensation on every
    body."""
    for body in spec.bodies[1:]:
        body.gravcomp = 0.0 if params.gravity else 1.0


def add_grasp_site(body: mujoco.MjsBody, pos: Sequence[float]) -> None:
    body.add_site(name=GRASP_SITE, pos=list(pos), size=[0.01, 0, 0], rgba=[0, 1, 0, 1], group=4)

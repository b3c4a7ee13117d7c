"""A minimal URDF reader (xml.etree): joints and link inertials, enough to build a robot's
kinematic chain with MjSpec (add_urdf_link places a joint's child link). Meshes, visuals and collisions are
ignored."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from mobilemani_rl.assets.robots.builder import add_link
from mobilemani_rl.utils.rotations import quat_from_matrix, quat_mul

# third_party/ sits at the repository root, next to the package (the project is installed editable).
THIRD_PARTY = Path(__file__).resolve().parents[3] / "third_party"
G1_URDF = THIRD_PARTY / "agibot_g1" / "G1_omnipicker.urdf"
# RobotEra's STAR1 humanoid with its two XHAND1 hands; the XHand robot's hand is its right hand.
XHAND_URDF = THIRD_PARTY / "robotera_xhand" / "l3_with_hand_fixedpin_xml.urdf"


@dataclass(frozen=True)
class UrdfJoint:
    name: str
    type: str
    parent: str
    child: str
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    axis: tuple[float, float, float]
    limits: tuple[float, float] | None

    @property
    def quat(self) -> np.ndarray:
        """The origin's rotation as a (w, x, y, z) quaternion."""
        return quat_from_rpy(self.rpy)


@dataclass(frozen=True)
class UrdfInertial:
    mass: float
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    # (ixx, iyy, izz, ixy, ixz, iyz): MuJoCo's fullinertia order, in the inertial frame
    fullinertia: tuple[float, float, float, float, float, float]


@dataclass(frozen=True)
class UrdfCylinder:
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float]
    length: float
    radius: float


@dataclass(frozen=True)
class Urdf:
    joints: dict[str, UrdfJoint]
    inertials: dict[str, UrdfInertial]  # links without an <inertial> are absent
    cylinders: dict[str, UrdfCylinder]  # each link's first cylinder <collision>, where it has one


def rpy_matrix(rpy: tuple[float, float, float]) -> np.ndarray:
    """URDF fixed-axis roll-pitch-yaw: R = Rz(yaw) @ Ry(pitch) @ Rx(roll)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def quat_from_rpy(rpy: tuple[float, float, float]) -> np.ndarray:
    quat = np.asarray(quat_from_matrix(rpy_matrix(rpy)), float)
    return quat if quat[0] >= 0 else -quat


def _floats(text: str | None, default: str) -> tuple[float, ...]:
    return tuple(float(v) for v in (text if text is not None else default).split())


def _origin(element: ET.Element | None) -> tuple[tuple[float, ...], tuple[float, ...]]:
    if element is None:
        return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    return _floats(element.get("xyz"), "0 0 0"), _floats(element.get("rpy"), "0 0 0")


def load_urdf(path: str | Path) -> Urdf:
    root = ET.parse(path).getroot()
    joints = {}
    for joint in root.findall("joint"):
        xyz, rpy = _origin(joint.find("origin"))
        axis = joint.find("axis")
        limit = joint.find("limit")
        limits = None
        if limit is not None and joint.get("type") in ("revolute", "prismatic"):
            limits = (float(limit.get("lower", "0")), float(limit.get("upper", "0")))
        joints[joint.get("name")] = UrdfJoint(
            name=joint.get("name"),
            type=joint.get("type"),
            parent=joint.find("parent").get("link"),
            child=joint.find("child").get("link"),
            xyz=xyz,
            rpy=rpy,
            axis=_floats(axis.get("xyz") if axis is not None else None, "1 0 0"),
            limits=limits,
        )
    inertials = {}
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        xyz, rpy = _origin(inertial.find("origin"))
        tensor = inertial.find("inertia")
        inertials[link.get("name")] = UrdfInertial(
            mass=float(inertial.find("mass").get("value")),
            xyz=xyz,
            rpy=rpy,
            fullinertia=tuple(float(tensor.get(k, "0")) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")),
        )
    cylinders = {}
    for link in root.findall("link"):
        for collision in link.findall("collision"):
            cylinder = collision.find("geometry/cylinder")
            if cylinder is not None:
                xyz, rpy = _origin(collision.find("origin"))
                cylinders[link.get("name")] = UrdfCylinder(
                    xyz, rpy, float(cylinder.get("length")), float(cylinder.get("radius"))
                )
                break
    return Urdf(joints=joints, inertials=inertials, cylinders=cylinders)


def rotate(quat, vec) -> np.ndarray:
    """Rotate a 3-vector by a unit (w, x, y, z) quaternion."""
    w, *xyz = quat
    xyz = np.asarray(xyz, float)
    vec = np.asarray(vec, float)
    return vec + 2 * w * np.cross(xyz, vec) + 2 * np.cross(xyz, np.cross(xyz, vec))


def set_urdf_inertial(body: mujoco.MjsBody, inertial: UrdfInertial, quat=None) -> None:
    """The link's URDF inertial as the body's explicit inertial; `quat` rotates the link frame into the body
    frame (None: the body frame is the link frame)."""
    ipos, iquat = np.asarray(inertial.xyz, float), quat_from_rpy(inertial.rpy)
    if quat is not None:
        ipos, iquat = rotate(quat, ipos), quat_mul(np.asarray(quat, float), iquat)
    body.explicitinertial = True
    body.mass = inertial.mass
    body.ipos = list(ipos)
    body.iquat = list(iquat)
    body.fullinertia = list(inertial.fullinertia)


def add_urdf_link(parent: mujoco.MjsBody, urdf: Urdf, joint: UrdfJoint, quat=None) -> mujoco.MjsBody:
    """The URDF joint's child link at the joint origin, with the link's inertial if it has one. `quat`: an
    extra rotation of the parent frame (where the parent body's frame is not the URDF parent link's)."""
    pos = np.asarray(joint.xyz, float)
    rot = joint.quat
    if quat is not None:
        pos = rotate(quat, pos)
        rot = quat_mul(np.asarray(quat, float), rot)
    body = add_link(parent, joint.child, pos, rot)
    inertial = urdf.inertials.get(joint.child)
    if inertial is not None:
        set_urdf_inertial(body, inertial)
    return body

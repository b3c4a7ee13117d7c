"""The XHand's hand equals the right XHAND1 hand of the vendored RobotEra URDF (third_party/robotera_xhand):
joint origins, axes and limits, link inertials and phalanx lengths, read from both the URDF file and the
compiled MjModel. The URDF's hand link maps onto the hand frame (xhand_right_base_link) by one fixed rotation:
fingers -z -> -x, palm normal +y -> +z, index side +x -> +y."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest

from mobilemani_rl.assets.robots.urdf import THIRD_PARTY, XHAND_URDF, rpy_matrix
from mobilemani_rl.assets.robots.xhand import HAND_JOINTS, PALM_LINK, XHAND, build_xhand_spec

URDF_HAND_LINK = "right_hand_link"
# Columns: the URDF hand link's x, y, z axes in the hand frame.
MOUNT = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def _floats(text):
    return np.array([float(v) for v in text.split()])


def _mat(quat) -> np.ndarray:
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, np.asarray(quat, float))
    return mat.reshape(3, 3)


@pytest.fixture(scope="module")
def model():
    return build_xhand_spec().compile()


@pytest.fixture(scope="module")
def urdf():
    root = ET.parse(XHAND_URDF).getroot()
    joints = {j.get("name"): j for j in root.findall("joint")}
    links = {link.get("name"): link for link in root.findall("link")}
    return joints, links


def _urdf_name(joint: str) -> str:
    return joint + "_joint" if joint.endswith("_bend") else joint


def _origin(element):
    origin = element.find("origin")
    return _floats(origin.get("xyz")), rpy_matrix(tuple(_floats(origin.get("rpy"))))


def test_vendored_files_present():
    assert XHAND_URDF.is_file()
    licence = (THIRD_PARTY / "robotera_xhand" / "LICENSE").read_text()
    assert "BSD 3-Clause" in licence and "RobotEra" in licence
    assert "roboterax/models" in (THIRD_PARTY / "robotera_xhand" / "README.md").read_text()


def test_all_twelve_hand_joints_come_from_the_urdf(urdf):
    joints, _ = urdf
    revolute = {n for n, j in joints.items() if n.startswith("right_hand_") and j.get("type") == "revolute"}
    assert {_urdf_name(j) for j in HAND_JOINTS} == revolute


@pytest.mark.parametrize("joint_name", HAND_JOINTS)
def test_hand_joint_matches_urdf(model, urdf, joint_name):
    joints, links = urdf
    element = joints[_urdf_name(joint_name)]
    parent, child = element.find("parent").get("link"), element.find("child").get("link")
    xyz, rot = _origin(element)
    joint = model.joint(joint_name)
    body = model.body(child)
    assert joint.bodyid[0] == body.id
    parent_body = model.body(body.parentid[0]).name
    if parent == URDF_HAND_LINK:  # the mount: the fixed rotation onto the hand frame
        assert parent_body == PALM_LINK
        xyz, rot = MOUNT @ xyz, MOUNT @ rot
    else:
        assert parent_body == parent
    np.testing.assert_allclose(body.pos, xyz, atol=1e-9)
    np.testing.assert_allclose(_mat(body.quat), rot, atol=1e-9)
    # The joint axis in the child link's own (URDF) frame.
    np.testing.assert_allclose(joint.axis, _floats(element.find("axis").get("xyz")), atol=1e-12)
    limit = element.find("limit")
    limits = [float(limit.get("lower")), float(limit.get("upper"))]
    np.testing.assert_allclose(joint.range, limits, atol=1e-12)
    np.testing.assert_allclose(model.actuator(joint_name).ctrlrange, limits, atol=1e-12)
    inertial = links[child].find("inertial")
    assert body.mass[0] == pytest.approx(float(inertial.find("mass").get("value")), abs=1e-12)
    np.testing.assert_allclose(body.ipos, _floats(inertial.find("origin").get("xyz")), atol=1e-9)


def test_palm_inertial_is_the_urdf_hand_link(model, urdf):
    _, links = urdf
    inertial = links[URDF_HAND_LINK].find("inertial")
    palm = model.body(PALM_LINK)
    assert palm.mass[0] == pytest.approx(float(inertial.find("mass").get("value")), abs=1e-12)
    np.testing.assert_allclose(palm.ipos, MOUNT @ _floats(inertial.find("origin").get("xyz")), atol=1e-9)


@pytest.mark.parametrize("digit", ["thumb", "index", "mid", "ring", "pinky"])
def test_phalanx_lengths_match_urdf(model, urdf, digit):
    """Each phalanx capsule runs from its joint to the next joint's origin (the distal one to the URDF's
    fixed fingertip frame)."""
    joints, _ = urdf
    by_parent = {j.find("parent").get("link"): j for j in joints.values() if j.get("type") != "fixed"}
    tips = {j.find("parent").get("link"): j for j in joints.values() if j.get("type") == "fixed"}
    proximal = {"thumb": "thumb_rota_link1", "index": "index_rota_link1"}.get(digit, f"{digit}_link1")
    proximal = "right_hand_" + proximal
    distal = by_parent[proximal].find("child").get("link")
    for link, nxt in ((proximal, by_parent[proximal]), (distal, tips[distal])):
        length = _floats(nxt.find("origin").get("xyz"))
        body = model.body(link)
        (geom,) = [g for g in range(model.ngeom) if model.geom_bodyid[g] == body.id]
        assert model.geom_type[geom] == mujoco.mjtGeom.mjGEOM_CAPSULE
        assert 2 * model.geom_size[geom][1] == pytest.approx(np.linalg.norm(length), abs=1e-9)
        np.testing.assert_allclose(model.geom_pos[geom], length / 2, atol=1e-9)
        axis = _mat(model.geom_quat[geom])[:, 2]
        assert abs(axis @ length) / np.linalg.norm(length) == pytest.approx(1.0, abs=1e-9)
    # The fingertip point: the reference's offset in the distal link's frame.
    tip = model.site(XHAND.finger_sites[["pinky", "ring", "mid", "index", "thumb"].index(digit)])
    assert tip.bodyid[0] == model.body(distal).id
    offset = (0.03, 0, -0.01) if digit == "thumb" else (0, 0.01, -0.03)
    np.testing.assert_allclose(tip.pos, offset, atol=1e-12)


def test_hand_frame_conventions(model):
    """Straight fingers point along -x of the hand frame, the index on +y; flexing them turns them toward +z
    (the palm normal), where the palm point sits in front of the palm face."""
    data = mujoco.MjData(model)
    hand_qpos = [model.joint(j).qposadr[0] for j in HAND_JOINTS]

    def local(site):
        body = data.body(PALM_LINK)
        return body.xmat.reshape(3, 3).T @ (data.site(site).xpos - body.xpos)

    data.qpos[hand_qpos] = 0.0
    mujoco.mj_kinematics(model, data)
    mid, index, pinky = (local(f"right_hand_{f}_tip") for f in ("mid", "index", "pinky"))
    assert mid[0] < -0.18 and index[1] > mid[1] > pinky[1]
    data.qpos[model.joint("right_hand_mid_joint1").qposadr[0]] = 1.0
    mujoco.mj_kinematics(model, data)
    assert local("right_hand_mid_tip")[2] > mid[2] + 0.05
    palm_box = [g for g in range(model.ngeom) if model.geom_bodyid[g] == model.body(PALM_LINK).id][0]
    face = model.geom_pos[palm_box][2] + model.geom_size[palm_box][2]
    assert local("palm")[2] > face

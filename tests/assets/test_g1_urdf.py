"""The G1's right arm equals the vendored AgiBot URDF (third_party/agibot_g1): joint origins, axes, limits and
link inertials, read from both the URDF file and the compiled MjModel."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest

from mobilemani_rl.assets.robots.g1 import ARM_JOINTS, DEFAULT_ARM, REFERENCE_DEFAULT_ARM, build_g1_spec
from mobilemani_rl.assets.robots.urdf import G1_URDF, THIRD_PARTY, quat_from_rpy, rpy_matrix


def _floats(text):
    return np.array([float(v) for v in text.split()])


@pytest.fixture(scope="module")
def model():
    return build_g1_spec().compile()


@pytest.fixture(scope="module")
def urdf_root():
    return ET.parse(G1_URDF).getroot()


def test_vendored_files_present():
    assert G1_URDF.is_file()
    licence = (THIRD_PARTY / "agibot_g1" / "LICENSE.txt").read_text()
    assert "Mozilla Public License" in licence and "Version 2.0" in licence
    assert "genie_sim" in (THIRD_PARTY / "agibot_g1" / "README.md").read_text()


def _same_rotation(q1, q2):
    return abs(abs(float(np.dot(q1, q2))) - 1.0) < 1e-9


def test_rpy_convention():
    # URDF rpy is fixed-axis X then Y then Z: R = Rz @ Ry @ Rx
    rpy = (0.3, -0.7, 1.1)
    quat = quat_from_rpy(rpy)
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, quat)
    np.testing.assert_allclose(mat.reshape(3, 3), rpy_matrix(rpy), atol=1e-12)


@pytest.mark.parametrize("joint_name", ARM_JOINTS)
def test_arm_joint_matches_urdf(model, urdf_root, joint_name):
    (element,) = [j for j in urdf_root.findall("joint") if j.get("name") == joint_name]
    parent, child = element.find("parent").get("link"), element.find("child").get("link")
    origin = element.find("origin")
    joint = model.joint(joint_name)
    body = model.body(child)
    assert joint.bodyid[0] == body.id
    assert model.body(body.parentid[0]).name == parent
    np.testing.assert_allclose(body.pos, _floats(origin.get("xyz")), atol=1e-9)
    expected = np.zeros(4)
    mat = rpy_matrix(tuple(_floats(origin.get("rpy"))))
    mujoco.mju_mat2Quat(expected, mat.flatten())
    assert abs(abs(float(np.dot(body.quat, expected))) - 1.0) < 1e-6, (body.quat, expected)
    np.testing.assert_allclose(joint.axis, _floats(element.find("axis").get("xyz")), atol=1e-12)
    limit = element.find("limit")
    np.testing.assert_allclose(
        joint.range, [float(limit.get("lower")), float(limit.get("upper"))], atol=1e-12
    )
    actuator = model.actuator(joint_name)
    np.testing.assert_allclose(actuator.ctrlrange, joint.range, atol=1e-12)

    # Link inertial: mass, centre of mass, and the full inertia tensor (rotated into the body frame).
    (link,) = [lk for lk in urdf_root.findall("link") if lk.get("name") == child]
    inertial = link.find("inertial")
    assert body.mass[0] == pytest.approx(float(inertial.find("mass").get("value")), abs=1e-12)
    np.testing.assert_allclose(body.ipos, _floats(inertial.find("origin").get("xyz")), atol=1e-9)
    t = {k: float(v) for k, v in inertial.find("inertia").attrib.items()}
    tensor = np.array(
        [[t["ixx"], t["ixy"], t["ixz"]], [t["ixy"], t["iyy"], t["iyz"]], [t["ixz"], t["iyz"], t["izz"]]]
    )
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, body.iquat)
    rot = rot.reshape(3, 3)
    np.testing.assert_allclose(rot @ np.diag(body.inertia) @ rot.T, tensor, atol=1e-10)


def test_arm_chain_mount(model, urdf_root):
    """The fixed torso joints (lift and waist at 0) place the arm's base as in the URDF, up to the +90° yaw
    that maps the URDF's +x forward onto the robot's +y forward."""
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    base = data.body("base_link")
    shoulder = data.body("arm_r_base_link")
    rel = base.xmat.reshape(3, 3).T @ (shoulder.xpos - base.xpos)
    # URDF: body_link1 at z 0.6485, body_link2 +0.131 x, arm_base_link +0.305 up, arm_r_base_link 0.025 right.
    np.testing.assert_allclose(rel, [0.025, 0.131, 0.6485 + 0.305], atol=1e-9)


def test_default_arm_is_the_reference_palm_pose_with_margin(model):
    """The default arm puts the palm where the reference's default joint values do (same position and
    orientation), with the joints away from the URDF limits and the wrist off its singularity (j6 = 0)."""
    data = mujoco.MjData(model)
    qpos = [model.joint(name).qposadr[0] for name in ARM_JOINTS]

    def palm(arm):
        data.qpos[qpos] = arm
        mujoco.mj_kinematics(model, data)
        body = data.body("gripper_r_center_link")
        return body.xpos.copy(), body.xmat.reshape(3, 3).copy()

    (ref_pos, ref_mat), (pos, mat) = palm(REFERENCE_DEFAULT_ARM), palm(DEFAULT_ARM)
    np.testing.assert_allclose(pos, ref_pos, atol=1e-3)
    np.testing.assert_allclose(mat, ref_mat, atol=2e-3)
    limits = np.array([model.joint(name).range for name in ARM_JOINTS])
    margin = np.minimum(np.array(DEFAULT_ARM) - limits[:, 0], limits[:, 1] - np.array(DEFAULT_ARM))
    assert margin.min() >= 0.25 and abs(DEFAULT_ARM[5]) > 0.5, margin

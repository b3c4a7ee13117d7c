"""Each reward term, the grasp flag and success on hand-constructed states."""

import numpy as np
import pytest

from mobilemani_rl.envs.config import RewardWeights, SuccessCfg
from mobilemani_rl.envs.frames import Frames
from mobilemani_rl.envs.rewards import RewardContext, TaskDistances, grasp_flag, reward_terms, total_reward
from mobilemani_rl.utils.rotations import quat_from_euler

IDENTITY = np.array([[1.0, 0.0, 0.0, 0.0]])
# Palm pointing along world +y: +z rotated by -90° about x.
PALM_FORWARD = quat_from_euler(np.array([[-np.pi / 2, 0.0, 0.0]]))


def make_frames(palm, fingers, grasp, palm_quat=PALM_FORWARD, bodies=None) -> Frames:
    palm, grasp = np.array([palm], float), np.array([grasp], float)
    fingers = np.array([fingers], float)
    nf = fingers.shape[1]
    bodies = np.array([bodies if bodies is not None else [[0.0, -1.0, 0.5]] * 2], float)
    zeros3 = np.zeros((1, 3))
    return Frames(
        palm_pos=palm,
        palm_quat=palm_quat,
        palm_linvel=zeros3,
        palm_angvel=zeros3,
        finger_pos=fingers,
        finger_quat=np.tile(IDENTITY, (1, nf, 1)),
        finger_linvel=np.zeros((1, nf, 3)),
        finger_angvel=np.zeros((1, nf, 3)),
        body_pos=bodies,
        hand_pos=palm,
        hand_quat=palm_quat,
        base_pos=zeros3,
        base_quat=IDENTITY,
        grasp_pos=grasp,
        grasp_quat=IDENTITY,
        grasp_linvel=zeros3,
        joint_pos=np.zeros((1, 10)),
        joint_vel=np.zeros((1, 10)),
        joint_acc=np.zeros((1, 10)),
    )


def evaluate(frames, actions, goal, d0=0.3, palm_rot_target=None):
    ctx = RewardContext(np.array([goal], float), np.array([d0]), np.array([1.0]), palm_rot_target)
    d = TaskDistances.measure(frames, ctx.goal_pos)
    grasped = grasp_flag(d, SuccessCfg())
    return reward_terms(frames, np.array([actions], float), ctx, d, grasped, SuccessCfg()), d, grasped


def test_reach_phase_terms():
    # Palm 0.5 m behind the grasp point along -y, palm already pointing +y; fingers around the palm.
    frames = make_frames(
        palm=[0, -0.5, 0.8], fingers=[[0, -0.5, 0.8], [0, -0.5, 0.78], [0, -0.5, 0.82]], grasp=[0, 0, 0.8]
    )
    actions = [0.2, 0.5, 0.0, 0.1, 0.0, 0.0, 0.4]
    terms, d, grasped = evaluate(frames, actions, goal=[0, 0, 1.0], d0=0.2)
    assert not grasped[0]
    # diff_reach_pos_action = ||clip(grasp - palm) - a[0:3]|| = ||(0, 0.5, 0) - (0.2, 0.5, 0)||
    assert terms["diff_reach_pos_action"][0] == pytest.approx(0.2)
    # Palm direction already equals the grasp direction: target rotation 0.
    assert terms["diff_reach_rot_action"][0] == pytest.approx(0.1, abs=1e-6)
    # Default hand action (1.0) vs a[6] = 0.4.
    assert terms["diff_reach_joint_action"][0] == pytest.approx(0.6)
    assert terms["diff_hand_object"][0] == pytest.approx(0.5)
    assert terms["diff_hand_thumb_object"][0] == pytest.approx(np.hypot(0.5, 0.02))
    assert terms["diff_hand_finger_object"][0] == pytest.approx((0.5 + 2 * np.hypot(0.5, 0.02)) / 3)
    assert terms["diff_hand_body_object"][0] == pytest.approx(np.hypot(1.0, 0.3))
    assert terms["diff_object_goal"][0] == pytest.approx(0.2 / 0.2)
    for name in (
        "bonus_grasp_object",
        "diff_move_pos_action",
        "diff_move_rot_action",
        "bonus_object_goal",
        "diff_reach_palm_rot_action",
    ):
        assert terms[name][0] == 0.0, name


def test_reach_rotation_target_is_clipped_euler_of_shortest_arc():
    # Palm pointing up (+z): the rotation onto +y is -90° about x, clipped to -1.
    frames = make_frames(
        palm=[0, -0.5, 0.8], fingers=[[0, -0.5, 0.8]] * 3, grasp=[0, 0, 0.8], palm_quat=IDENTITY
    )
    terms, _, _ = evaluate(frames, [0, 0, 0, 0, 0, 0, 1.0], goal=[0, 0, 1.0])
    assert terms["diff_reach_rot_action"][0] == pytest.approx(1.0)


def test_grasp_phase_terms_and_bonuses():
    grasp = [0.0, 0.0, 0.8]
    frames = make_frames(
        palm=[0, -0.01, 0.8], fingers=[[0, -0.01, 0.8], [0, 0, 0.77], [0, 0, 0.83]], grasp=grasp
    )
    goal = [0.0, 0.03, 0.82]  # within 5 cm: success, goal bonus
    actions = [0.0, 0.1, 0.0, 0.0, 0.0, 0.0, -1.0]
    terms, d, grasped = evaluate(frames, actions, goal=goal, d0=0.3)
    assert grasped[0]
    assert terms["bonus_grasp_object"][0] == 1.0
    assert terms["bonus_object_goal"][0] == 1.0
    to_goal = np.array(goal) - np.array(grasp)
    assert terms["diff_move_pos_action"][0] == pytest.approx(np.linalg.norm(to_goal / 0.3 - actions[:3]))
    assert terms["diff_object_goal"][0] == pytest.approx(np.linalg.norm(to_goal) / 0.3)
    for name in ("diff_reach_pos_action", "diff_reach_rot_action", "diff_reach_joint_action"):
        assert terms[name][0] == 0.0, name


def test_move_rotation_target_points_palm_against_the_motion():
    # Moving the grasp point toward -y (pulling a door): the palm should point +y, which it already does.
    frames = make_frames(palm=[0, 0, 0.8], fingers=[[0, 0, 0.8]] * 3, grasp=[0, 0, 0.8])
    terms, _, grasped = evaluate(frames, [0, 0, 0, 0.3, 0, 0, 0], goal=[0, -0.3, 0.8])
    assert grasped[0]
    assert terms["diff_move_rot_action"][0] == pytest.approx(0.3, abs=1e-6)


def test_grasp_flag_needs_palm_thumb_and_fingers_close():
    cfg = SuccessCfg()
    far_thumb = make_frames(
        palm=[0, -0.05, 0.8], fingers=[[0, -0.05, 0.8], [0, 0, 0.8], [0, 0, 0.95]], grasp=[0, 0, 0.8]
    )
    d = TaskDistances.measure(far_thumb, np.zeros((1, 3)))
    assert d.thumb[0] == pytest.approx(0.15) and not grasp_flag(d, cfg)[0]


def test_palm_rotation_term_uses_pitch_of_target_relative_rotation():
    frames = make_frames(
        palm=[0, -0.5, 0.8], fingers=[[0, -0.5, 0.8]] * 3, grasp=[0, 0, 0.8], palm_quat=IDENTITY
    )
    target = quat_from_euler(np.array([[0.0, 0.4, 0.0]]))  # q_rot90 ⊗ q_palm⁻¹ has pitch 0.4
    terms, _, _ = evaluate(frames, [0, 0, 0, 0, 0.1, 0, 1.0], goal=[0, 0, 1.0], palm_rot_target=target)
    assert terms["diff_reach_palm_rot_action"][0] == pytest.approx(0.3)


def test_total_reward_weights_and_clip():
    terms = {name: np.array([1.0]) for name in RewardWeights.__dataclass_fields__}
    total, weighted = total_reward(terms, RewardWeights(), clip=10.0)
    expected = sum(getattr(RewardWeights(), name) for name in terms)
    assert total[0] == pytest.approx(expected)
    assert weighted["diff_hand_finger_object"][0] == -2.0 and weighted["bonus_object_goal"][0] == 2.0
    big = {name: np.array([100.0]) for name in terms}
    assert total_reward(big, RewardWeights(), clip=10.0)[0][0] == -10.0

"""Tuning of the scripted reference policy (mobilemani_rl.scripted.policy). Each robot's description holds its
own (RobotDescription.scripted); docs/results/fidelity.md says why each value is what it is and what it
measured. It lives beside the robot descriptions, not the policy: the assets cannot import the policy, which
imports the env.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class ScriptedPolicyCfg:
    pos_gain: float = 12.0  # action per metre of error (saturates at 1 = 2.5 cm per step)
    rot_gain: float = 4.0
    pregrasp_offset: float = 0.08  # m in front of the grasp point along the approach direction
    pick_pregrasp_offset: float = 0.15  # above a rigid object's centre of mass: clears tall objects
    pick_finger_yaw: float | None = (
        None  # rad left of the robot's heading that a top-down pick's fingers point
    )
    pick_grip_shift: float = 0.0  # grip_shift of a top-down pick
    # A top-down pick descends at most this action (x 2.5 cm per step) while the base slides faster than
    # base_moving_speed (m/s): the IK makes up for the arm's descent by moving the base forward, which lags.
    pick_descent_while_moving: float | None = None
    base_moving_speed: float = 0.05
    pregrasp_tolerance: float = 0.015
    pregrasp_alignment: float = 0.985  # cosine between palm and approach directions needed to go in (~10°)
    grasp_depth: float = (
        0.0  # m past the grasp point (along the approach direction) where the palm point stops
    )
    pick_grasp_depth: float = 0.0  # grasp_depth of a top-down pick
    grip_shift: float = 0.0  # m along the hand frame's +x (the XHand's wrist side) where the palm point stops
    lid_grip_shift: float = 0.0  # the same at a lid's edge
    grasp_tolerance: float = 0.012
    blocked_radius: float = (
        0.05  # the palm stopped this close to the grasp point (touching the object): close
    )
    blocked_speed: float = 0.01  # m/s
    close_steps: int = 8
    # Hand postures (joint name -> rad) that replace the robot's own for this policy only (the env's reset
    # posture stays): open_hand over its default posture while the hand is open (approaching, pushing lids
    # shut), pick_hand over its grasp posture (RobotDescription.grasp_hand_qpos) in a top-down pick.
    open_hand: dict[str, float] = field(default_factory=dict)
    pick_hand: dict[str, float] = field(default_factory=dict)
    follow_handle: bool = True  # approach from the grip's free side (else along the grasp direction)
    approach_from_below: bool = (
        True  # else a grip facing down (under a dropped door) is approached horizontally
    )
    # A grip whose lower end of travel (the grip or its goal, whichever is lower) sits below low_grip_height
    # (m above the floor) is approached with the palm tilted down, by low_grip_tilt_rate rad per metre below
    # it, at most low_grip_max_tilt: an arm on a fixed torso reaches lower with its palm turned down than
    # pointing straight ahead (None: never tilted).
    low_grip_height: float | None = None
    low_grip_tilt_rate: float = 0.0
    low_grip_max_tilt: float = 0.0
    push_lids_shut: bool = False  # close a lid by pushing it with the open hand instead of grasping its edge
    hooked_lips: tuple[
        str, ...
    ] = ()  # categories whose thin lid lip the fingertips hook from in front to open it
    lip_hook_shift: float = 0.0  # grip_shift of that hook: the palm point stays this far toward the wrist
    lip_hook_depth: float = 0.0  # grasp_depth of that hook
    move_follow: float = 1.0  # weight of keeping the palm on the grip's free side while moving
    move_rotation: float = (
        0.0  # weight of the reward's palm-rotation target while moving (it fights the grasp)
    )
    move_ramp_steps: int = (
        40  # steps over which a pull speeds up to full: a jerk on a resting link tears the grip off
    )
    regrasp_distance: float = (
        0.06  # m between palm and grip that counts as a lost grip while pulling: approach again
    )
    hold_gain: float = 1.0  # weight of keeping the palm where it closed on the link while pulling
    arc_lead: float = (
        0.1  # m of arc ahead of a hinged grip that the hand moves toward (0: straight at the goal)
    )

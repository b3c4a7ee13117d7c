"""Compose robot + object + stage + ground into one MjModel and index everything the env reads or writes."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mobilemani_rl.assets.collision import WORLD_CONTACT
from mobilemani_rl.assets.objects import ObjectKind, ObjectModel
from mobilemani_rl.assets.objects.model import GRASP_SITE, ROOT_BODY
from mobilemani_rl.assets.robots import RobotDescription
from mobilemani_rl.assets.scenes import Placement, add_scene
from mobilemani_rl.assets.stage import OBJECT_PREFIX, STAGE_HALF
from mobilemani_rl.envs.config import PhysicsCfg, ResetCfg


@dataclass(frozen=True)
class SceneIndex:
    """Ids and addresses into the compiled scene, as integer arrays ready for fancy indexing."""

    ik_qpos: np.ndarray
    ik_dof: np.ndarray
    ik_joint: np.ndarray  # joint ids
    ik_is_hinge: np.ndarray  # bool; the others are slides
    ik_is_base: np.ndarray  # bool; the mobile base's yaw and slide, the others are arm joints
    ik_act: np.ndarray
    ik_limits: np.ndarray  # (9, 2)
    hand_qpos: np.ndarray
    hand_dof: np.ndarray
    hand_act: np.ndarray
    hand_limits: np.ndarray  # (nh, 2)
    mimic_act: np.ndarray  # actuators that copy a hand joint's target
    mimic_leader: np.ndarray  # index into hand joints for each mimic actuator
    robot_qpos: np.ndarray  # every robot joint's qpos address
    robot_default_qpos: np.ndarray  # defaults for robot_qpos
    robot_act_qpos: np.ndarray  # for each actuator on a robot joint: its joint's qpos address
    robot_act: np.ndarray
    hand_body: int
    palm_site: int
    finger_sites: np.ndarray
    active_bodies: np.ndarray
    base_body: int
    robot_mocap: int
    stage_mocap: int
    object_root: int
    object_mocap: int  # -1 for free objects
    object_free_qpos: int  # -1 for fixed objects
    object_free_dof: int
    object_joint_qpos: int  # -1 without an operated joint
    object_joint_dof: int
    grasp_site: int
    grasp_body: int


@dataclass(frozen=True)
class IkJoints:
    """The joints one IK step moves, as columns of the IK chain's arrays."""

    qpos: np.ndarray
    joint: np.ndarray
    is_hinge: np.ndarray
    act: np.ndarray
    limits: np.ndarray  # (k, 2)


def ik_joints(index: SceneIndex, fixed_base: bool) -> IkJoints:
    """The whole chain, or the arm alone when the base is locked."""
    moved = ~index.ik_is_base if fixed_base else np.ones_like(index.ik_is_base)
    return IkJoints(
        index.ik_qpos[moved],
        index.ik_joint[moved],
        index.ik_is_hinge[moved],
        index.ik_act[moved],
        index.ik_limits[moved],
    )


def _add_stage_and_ground(spec: mujoco.MjSpec) -> None:
    ground = spec.worldbody.add_geom(
        name="ground", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[20, 20, 0.1], rgba=[0.45, 0.45, 0.45, 1]
    )
    ground.contype, ground.conaffinity = WORLD_CONTACT
    stage = spec.worldbody.add_body(name="stage", mocap=True, pos=[0, 1.0, -STAGE_HALF[2]])
    geom = stage.add_geom(
        name="stage", type=mujoco.mjtGeom.mjGEOM_BOX, size=list(STAGE_HALF), rgba=[0.1, 0.1, 0.1, 1]
    )
    geom.contype, geom.conaffinity = WORLD_CONTACT
    spec.worldbody.add_light(
        name="sun",
        pos=[0, -1, 4],
        dir=[0, 0.3, -1],
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        diffuse=[0.75, 0.75, 0.75],
        castshadow=False,
    )


def build_scene_spec(robot: RobotDescription, obj: ObjectModel, physics: PhysicsCfg) -> mujoco.MjSpec:
    # The robot's own spec is the scene's base; the object is attached under a name prefix.
    spec = robot.build_spec()
    spec.modelname = f"{robot.name}_{obj.object_id.replace('/', '_')}"
    spec.option.timestep = physics.timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.iterations = physics.solver_iterations
    spec.option.ls_iterations = physics.ls_iterations
    spec.visual.global_.offwidth = 1024
    spec.visual.global_.offheight = 1024
    spec.visual.quality.offsamples = 0
    _add_stage_and_ground(spec)
    spec.attach(obj.build_spec(), prefix=OBJECT_PREFIX, frame=spec.worldbody.add_frame())
    root = spec.body(OBJECT_PREFIX + ROOT_BODY)
    if obj.kind is ObjectKind.ARTICULATED:
        root.mocap = True
        spec.add_exclude(bodyname1=root.name, bodyname2="stage")
    else:
        root.add_freejoint(name=OBJECT_PREFIX + "free")
    return spec


def index_scene(model: mujoco.MjModel, robot: RobotDescription, obj: ObjectModel) -> SceneIndex:
    def joints(names) -> list:
        return [model.joint(n) for n in names]

    def act_of(names) -> np.ndarray:
        return np.array([model.actuator(n).id for n in names], dtype=int)

    ik, hand = joints(robot.ik_joints), joints(robot.hand_joints)
    robot_joint_ids = [j for j in range(model.njnt) if not model.joint(j).name.startswith(OBJECT_PREFIX)]
    robot_qpos = np.array([model.jnt_qposadr[j] for j in robot_joint_ids], dtype=int)
    defaults = np.array([robot.default_qpos.get(model.joint(j).name, 0.0) for j in robot_joint_ids])
    robot_act = np.array(
        [a for a in range(model.nu) if model.actuator_trnid[a, 0] in robot_joint_ids], dtype=int
    )
    root = model.body(OBJECT_PREFIX + ROOT_BODY)
    free = obj.kind is not ObjectKind.ARTICULATED
    free_joint = model.joint(OBJECT_PREFIX + "free") if free else None
    op_joint = model.joint(OBJECT_PREFIX + obj.joint) if obj.joint else None
    return SceneIndex(
        ik_qpos=np.array([j.qposadr[0] for j in ik]),
        ik_dof=np.array([j.dofadr[0] for j in ik]),
        ik_joint=np.array([j.id for j in ik]),
        ik_is_hinge=np.array([j.type[0] == mujoco.mjtJoint.mjJNT_HINGE for j in ik]),
        ik_is_base=np.isin(robot.ik_joints, robot.base_joints),
        ik_act=act_of(robot.ik_joints),
        ik_limits=np.array([j.range for j in ik]),
        hand_qpos=np.array([j.qposadr[0] for j in hand]),
        hand_dof=np.array([j.dofadr[0] for j in hand]),
        hand_act=act_of(robot.hand_joints),
        hand_limits=np.array([j.range for j in hand]),
        mimic_act=act_of(robot.hand_mimic),
        mimic_leader=np.array(
            [robot.hand_joints.index(lead) for lead in robot.hand_mimic.values()], dtype=int
        ),
        robot_qpos=robot_qpos,
        robot_default_qpos=defaults,
        robot_act_qpos=model.jnt_qposadr[model.actuator_trnid[robot_act, 0]],
        robot_act=robot_act,
        hand_body=model.body(robot.hand_body).id,
        palm_site=model.site(robot.palm_site).id,
        finger_sites=np.array([model.site(s).id for s in robot.finger_sites]),
        active_bodies=np.array([model.body(b).id for b in robot.active_bodies]),
        base_body=model.body(robot.base_body).id,
        robot_mocap=int(model.body_mocapid[model.body("Root").id]),
        stage_mocap=int(model.body_mocapid[model.body("stage").id]),
        object_root=root.id,
        object_mocap=int(model.body_mocapid[root.id]),
        object_free_qpos=int(free_joint.qposadr[0]) if free_joint else -1,
        object_free_dof=int(free_joint.dofadr[0]) if free_joint else -1,
        object_joint_qpos=int(op_joint.qposadr[0]) if op_joint else -1,
        object_joint_dof=int(op_joint.dofadr[0]) if op_joint else -1,
        grasp_site=model.site(OBJECT_PREFIX + GRASP_SITE).id,
        grasp_body=model.body(OBJECT_PREFIX + obj.grasp_body).id,
    )


def build_scene(
    robot: RobotDescription,
    obj: ObjectModel,
    physics: PhysicsCfg,
    reset: ResetCfg,
    placement: Placement | None = None,
) -> tuple[mujoco.MjModel, SceneIndex]:
    """The plain stage scene, decorated with a realistic room when a placement is given; the room keeps clear
    of where `reset` puts the object."""
    spec = build_scene_spec(robot, obj, physics)
    if placement is not None:
        add_scene(spec, placement, obj, reset.pick_y_offset, reset.table_height_jitter)
    model = spec.compile()
    return model, index_scene(model, robot, obj)

"""Geom -> label tables for segmentation: object 1, robot 2, everything else 0, as in the reference."""

from __future__ import annotations

import mujoco
import numpy as np

from mobilemani_rl.assets.objects.model import ROOT_BODY
from mobilemani_rl.assets.stage import OBJECT_PREFIX

LABEL_BACKGROUND, LABEL_OBJECT, LABEL_ROBOT = 0, 1, 2
OBJECT_ROOT = OBJECT_PREFIX + ROOT_BODY
ROBOT_ROOT = "Root"  # the robot's mocap root


def subtree(model: mujoco.MjModel, root: int) -> np.ndarray:
    """Boolean mask over bodies: inside the subtree rooted at `root` (parents precede children)."""
    inside = np.zeros(model.nbody, dtype=bool)
    inside[root] = True
    for body in range(root + 1, model.nbody):
        inside[body] = inside[model.body_parentid[body]]
    return inside


def geom_labels(
    model: mujoco.MjModel,
    object_root: str = OBJECT_ROOT,
    robot_root: str = ROBOT_ROOT,
) -> np.ndarray:
    """(ngeom,) uint8 label per geom, by the body it belongs to; absent roots label nothing."""
    body_label = np.zeros(model.nbody, dtype=np.uint8)
    for name, label in ((robot_root, LABEL_ROBOT), (object_root, LABEL_OBJECT)):
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
        if body >= 0:
            body_label[subtree(model, body)] = label
    return body_label[model.geom_bodyid]


def segment_labels(scene: mujoco.MjvScene, labels: np.ndarray) -> np.ndarray:
    """(ngeom + 1,) table from a segmentation pixel's id (scene geom index + 1, 0 = none) to its label."""
    table = np.zeros(scene.ngeom + 1, dtype=np.uint8)
    geom_type = int(mujoco.mjtObj.mjOBJ_GEOM)
    for index in range(scene.ngeom):
        geom = scene.geoms[index]
        if geom.objtype == geom_type and geom.segid >= 0:
            table[geom.segid + 1] = labels[geom.objid]
    return table

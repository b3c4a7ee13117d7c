"""Per-episode room repainting for rendered training data (domain randomisation of appearance).

A policy trained on the 16 train rooms' fixed colours learns their backgrounds as well as the task; in the 4
unseen test rooms it then misplaces its hand (docs/results/vla.md). Repainting the room for every exported
episode shows it many more backgrounds with the same geometry. Only the room changes: every colour of the
`scene/room` subtree and of a table with a body of its own, `scene/table` (materials, and geoms without one),
is blended toward a random colour by a random amount up to `strength`, and the room's lights are dimmed or
brightened together by up to `strength / 2`. The robot and the object keep their colours; nothing physical
changes.
"""

from __future__ import annotations

import mujoco
import numpy as np

from mobilemani_rl.assets.scenes.compose import ROOM_BODY, TABLE_BODY
from mobilemani_rl.render.segmentation import subtree


class RoomRepainter:
    """Repaints a model's room in place (`repaint`) and puts its built colours back (`restore`)."""

    def __init__(self, model: mujoco.MjModel) -> None:
        room = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, ROOM_BODY)
        if room < 0:
            raise ValueError(f"the model has no {ROOM_BODY!r} body to repaint (a scene without a room)")
        inside = subtree(model, room)
        table = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, TABLE_BODY)
        if table >= 0:
            inside |= subtree(model, table)
        room_geoms = np.flatnonzero(inside[model.geom_bodyid])
        materials = model.geom_matid[room_geoms]
        self.model = model
        self.geoms = room_geoms[materials < 0]  # geoms coloured by their own rgba
        self.materials = np.unique(materials[materials >= 0])
        self.lights = np.flatnonzero(inside[model.light_bodyid])
        self._geom_rgba = model.geom_rgba[self.geoms].copy()
        self._mat_rgba = model.mat_rgba[self.materials].copy()
        self._light_diffuse = model.light_diffuse[self.lights].copy()

    def repaint(self, rng: np.random.Generator, strength: float) -> None:
        """Blend each room colour toward its own random one by U(0, strength); scale the lights together."""
        if not 0.0 <= strength <= 1.0:
            raise ValueError(f"repaint strength must lie in [0, 1], got {strength}")
        self.restore()
        self.model.geom_rgba[self.geoms] = _blend(self._geom_rgba, rng, strength)
        self.model.mat_rgba[self.materials] = _blend(self._mat_rgba, rng, strength)
        scale = rng.uniform(1.0 - strength / 2, 1.0 + strength / 2)
        self.model.light_diffuse[self.lights] = np.clip(self._light_diffuse * scale, 0.0, 1.0)

    def restore(self) -> None:
        self.model.geom_rgba[self.geoms] = self._geom_rgba
        self.model.mat_rgba[self.materials] = self._mat_rgba
        self.model.light_diffuse[self.lights] = self._light_diffuse


def _blend(rgba: np.ndarray, rng: np.random.Generator, strength: float) -> np.ndarray:
    """(N, 4) colours, each blended toward its own uniform random RGB by U(0, strength); alpha kept."""
    out = rgba.copy()
    weight = rng.uniform(0.0, strength, (len(rgba), 1))
    out[:, :3] = (1.0 - weight) * rgba[:, :3] + weight * rng.uniform(0.0, 1.0, (len(rgba), 3))
    return out

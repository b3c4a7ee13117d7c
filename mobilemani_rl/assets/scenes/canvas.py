"""Visual-only primitives on a scene body: rooms never collide (contype = conaffinity = 0),
as in the reference."""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco

Paint = str | Sequence[float]  # a material name, or an rgba colour

BOX = mujoco.mjtGeom.mjGEOM_BOX
CYLINDER = mujoco.mjtGeom.mjGEOM_CYLINDER
SPHERE = mujoco.mjtGeom.mjGEOM_SPHERE
CAPSULE = mujoco.mjtGeom.mjGEOM_CAPSULE
ELLIPSOID = mujoco.mjtGeom.mjGEOM_ELLIPSOID


def yaw_quat(yaw: float) -> list[float]:
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


class Canvas:
    """Adds geoms to one body; `item` opens a child body for a piece of furniture at a floor pose."""

    def __init__(self, body: mujoco.MjsBody) -> None:
        self.body = body

    def item(self, x: float, y: float, yaw: float = 0.0, z: float = 0.0) -> Canvas:
        return Canvas(self.body.add_body(pos=[x, y, z], quat=yaw_quat(yaw)))

    def _geom(
        self,
        kind: mujoco.mjtGeom,
        size: Sequence[float],
        paint: Paint,
        **where: Sequence[float],
    ) -> mujoco.MjsGeom:
        geom = self.body.add_geom(
            type=kind,
            size=list(size) + [0.0] * (3 - len(size)),
            contype=0,
            conaffinity=0,
            **{k: list(v) for k, v in where.items()},
        )
        if isinstance(paint, str):
            geom.material = paint  # geom rgba left at its default so the material's colour applies
        else:
            geom.rgba = list(paint[:3]) + [paint[3] if len(paint) > 3 else 1.0]
        return geom

    def box(
        self, pos: Sequence[float], half: Sequence[float], paint: Paint, yaw: float = 0.0
    ) -> mujoco.MjsGeom:
        return self._geom(BOX, half, paint, pos=pos, quat=yaw_quat(yaw))

    def cylinder(
        self, pos: Sequence[float], radius: float, half_height: float, paint: Paint
    ) -> mujoco.MjsGeom:
        return self._geom(CYLINDER, (radius, half_height), paint, pos=pos)

    def sphere(self, pos: Sequence[float], radius: float, paint: Paint) -> mujoco.MjsGeom:
        return self._geom(SPHERE, (radius,), paint, pos=pos)

    def ellipsoid(self, pos: Sequence[float], radii: Sequence[float], paint: Paint) -> mujoco.MjsGeom:
        return self._geom(ELLIPSOID, radii, paint, pos=pos)

    def tube(
        self, start: Sequence[float], end: Sequence[float], radius: float, paint: Paint
    ) -> mujoco.MjsGeom:
        """A cylinder between two points (wheels, posts)."""
        return self._geom(CYLINDER, (radius,), paint, fromto=list(start) + list(end))

    def capsule(
        self,
        start: Sequence[float],
        end: Sequence[float],
        radius: float,
        paint: Paint,
    ) -> mujoco.MjsGeom:
        return self._geom(CAPSULE, (radius,), paint, fromto=list(start) + list(end))

"""`add_scene`: decorate the plain scene spec (mobilemani_rl/envs/scene.py) with a placement's room.

The whole room is one mocap body, `scene/room`, so the env can jitter it per reset (as the reference does:
x ~ U(-0.1, 0.1), y ~ U(-0.05, 0.05), no yaw) with
`mocap_pos[env, room_mocap] = model.body_pos[room] + offset` (see `sample_room_offsets`). A tabletop room
whose table height changes per episode (`table_jitter`) has its table in a second mocap body, `scene/table`,
which the env moves with the room plus the episode's height offset. Room geoms never
collide; the plain scene's stage and ground stay physical but move to a geom group the renderer does not
draw. Room frame: x as the world, y = 0 at the back wall's inner face.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from mobilemani_rl.assets.objects import ObjectModel, Place
from mobilemani_rl.assets.scenes.canvas import Canvas
from mobilemani_rl.assets.scenes.footprint import Footprint, object_footprint
from mobilemani_rl.assets.scenes.furniture import support_table
from mobilemani_rl.assets.scenes.layout import Rect, Wall, line_walls
from mobilemani_rl.assets.scenes.lot import build_parking_lot
from mobilemani_rl.assets.scenes.placements import Placement, check_setting
from mobilemani_rl.assets.scenes.rooms import (
    Opening,
    RoomBox,
    add_ceiling_lights,
    build_beyond,
    build_shell,
    decorate_walls,
)
from mobilemani_rl.assets.scenes.styles import INDOOR_STYLES, make_palette
from mobilemani_rl.assets.scenes.textures import Materials

ROOM_BODY = "scene/room"
TABLE_BODY = "scene/table"
HIDDEN_GROUP = 3  # MjvOption draws geom groups 0-2 by default
PLAIN_SCENE_GEOMS = ("ground", "stage")
WALL_GAP = 0.06  # object back -> wall; larger than the ±0.05 m y jitter so they never intersect
TABLE_LIP = 0.04  # table front edge in front of the object's front face
ROBOT_ZONE_Y = -2.6  # world y in front of which the robot (root y >= -2.0, base radius 0.26) never goes
CORRIDOR_HALF = 0.75  # x half-width kept clear from the robot to the object (base, arm, yaw jitter)


@dataclass
class RoomJitterCfg:
    x: tuple[float, float] = (-0.1, 0.1)
    y: tuple[float, float] = (-0.05, 0.05)


def sample_room_offsets(rng: np.random.Generator, n: int, cfg: RoomJitterCfg | None = None) -> np.ndarray:
    """(n, 3) offsets to add to the room body's compiled position at each reset."""
    cfg = cfg or RoomJitterCfg()
    return np.stack((rng.uniform(*cfg.x, n), rng.uniform(*cfg.y, n), np.zeros(n)), axis=1)


def add_scene(
    spec: mujoco.MjSpec,
    placement: Placement,
    obj: ObjectModel,
    pick_y_offset: float,
    table_jitter: float = 0.0,
) -> None:
    """Add the placement's room (or parking lot) around the object's slot, in place. `pick_y_offset` is the
    running reset config's, so the room keeps clear of where the env puts rigid objects; `table_jitter` its
    per-episode table height spread (a tabletop table then gets a body of its own whose legs reach the floor
    from as high as it may go)."""
    check_setting(obj, placement)
    for name in PLAIN_SCENE_GEOMS:
        spec.geom(name).group = HIDDEN_GROUP
    rng = placement.rng()
    materials = Materials(spec, rng)
    footprint = object_footprint(obj, placement, pick_y_offset)
    half = max(footprint.half_width, 0.2)
    corridor_half = max(CORRIDOR_HALF, half + 0.3)
    if placement.setting is Place.OUTDOOR:
        anchor = float(footprint.hi[1]) + rng.uniform(1.0, 2.0)
        body = spec.worldbody.add_body(name=ROOM_BODY, mocap=True, pos=[0.0, anchor, 0.0])
        canvas = Canvas(body)
        _add_sky(spec)
        keep_out = _keep_out(footprint, anchor, corridor_half, half)
        build_parking_lot(body, canvas, materials, rng, half, keep_out)
        return
    _build_indoor(spec, placement, obj, footprint, rng, materials, half, corridor_half, table_jitter)


def _build_indoor(
    spec: mujoco.MjSpec,
    placement: Placement,
    obj: ObjectModel,
    footprint: Footprint,
    rng: np.random.Generator,
    materials: Materials,
    half: float,
    corridor_half: float,
    table_jitter: float,
) -> None:
    style = INDOOR_STYLES[placement.style]
    palette = make_palette(style, materials, rng)
    lo, hi = footprint.lo, footprint.hi
    opening, table = None, None
    match placement.setting:
        case Place.WALL:
            anchor = hi[1] + WALL_GAP
        case Place.DOOR:
            # The wall is as deep as the closed door; the opening frames it with room for the x jitter.
            anchor = lo[1]
            top = hi[2] + (0.5 if obj.params.random_height else 0.0) + 0.1
            opening = Opening(
                lo[0] - 0.15, hi[0] + 0.15, max(0.0, lo[2] - 0.1), top, max(0.12, float(hi[1] - lo[1]))
            )
        case Place.TABLETOP:
            table_front = lo[1] - TABLE_LIP
            table_depth = (hi[1] - table_front) + rng.uniform(0.1, 0.35)
            anchor = table_front + table_depth + rng.uniform(0.0, 0.4)
            table = (
                max(half + rng.uniform(0.15, 0.5), 0.45),
                table_depth / 2,
                table_front - anchor + table_depth / 2,
            )
        case _:  # space: the object stands free in the room
            anchor = hi[1] + rng.uniform(1.0, 2.5)
    anchor = float(anchor)
    height = float(rng.uniform(*style.height))
    if opening is not None:
        height = max(height, opening.z1 + 0.4)
    width = float(rng.uniform(4.2, 7.0))
    shift = float(rng.uniform(-1.0, 1.0)) * max(0.0, width / 2 - corridor_half - 1.0)
    depth = anchor - ROBOT_ZONE_Y + rng.uniform(0.6, 1.4)
    room = RoomBox(shift - width / 2, shift + width / 2, depth, height)

    body = spec.worldbody.add_body(name=ROOM_BODY, mocap=True, pos=[0.0, anchor, 0.0])
    canvas = Canvas(body)
    build_shell(canvas, room, style, materials, rng, opening)
    if opening is not None:
        build_beyond(canvas, opening, style, materials, rng, outdoors=obj.category == "window")
    keep_out = _keep_out(footprint, anchor, corridor_half, half)
    if table is not None:
        table_hx, table_hy, table_y = table
        table_canvas = canvas
        if table_jitter > 0:
            table_canvas = Canvas(
                spec.worldbody.add_body(name=TABLE_BODY, mocap=True, pos=[0.0, anchor, 0.0])
            )
        support_table(
            table_canvas.item(0.0, table_y),
            table_hx,
            table_hy,
            placement.support_height,
            style.name,
            palette,
            rng,
            below_floor=table_jitter,
        )
        keep_out.append(Rect(-table_hx - 0.1, table_y - table_hy - 0.1, table_hx + 0.1, 0.2))
    walls = [
        Wall((room.x0, 0.0), (1.0, 0.0), room.x1 - room.x0),  # back wall, pieces face -y
        Wall((room.x1, 0.0), (0.0, -1.0), depth),  # right wall, facing -x
        Wall((room.x1, -depth), (-1.0, 0.0), room.x1 - room.x0),  # front wall, facing +y
        Wall((room.x0, -depth), (0.0, 1.0), depth),  # left wall, facing +x
    ]
    line_walls(canvas, walls, keep_out, style.furniture, palette, rng, fill=rng.uniform(0.6, 0.95))
    if rng.random() < 0.5:  # a rug in front of the slot (flat, the robot drives over it)
        canvas.box(
            (0.0, ROBOT_ZONE_Y / 2 - anchor + 0.5, 0.003),
            (rng.uniform(0.7, 1.1), rng.uniform(0.8, 1.2), 0.003),
            materials.textured("speckle", palette.fabric, 3.0),
        )
    clear_above = opening.z1 if opening else float(hi[2])
    decorate_walls(canvas, room, materials, rng, back_clear_above=clear_above)
    add_ceiling_lights(body, canvas, room, style, palette.lamp, rng)


def _keep_out(footprint: Footprint, anchor: float, corridor_half: float, half: float) -> list[Rect]:
    """Room-frame rectangles kept free: the robot's area up to the object's front, and the object's slot."""
    front = float(footprint.lo[1]) - anchor
    return [
        Rect(-corridor_half, ROBOT_ZONE_Y - anchor, corridor_half, front - 0.1),
        Rect(-half - 0.15, front - 0.3, half + 0.15, 0.2),
    ]


def _add_sky(spec: mujoco.MjSpec) -> None:
    spec.add_texture(
        name="scene/sky",
        type=mujoco.mjtTexture.mjTEXTURE_SKYBOX,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_GRADIENT,
        rgb1=[0.45, 0.65, 0.9],
        rgb2=[0.95, 0.95, 1.0],
        width=256,
        height=256,
    )

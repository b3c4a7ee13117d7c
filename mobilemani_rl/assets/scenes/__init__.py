"""Scene placements: 5 settings x 20 procedural rooms / lots (16 train + 4 test), decorating the env's scene.

Wiring: `add_scene(build_scene_spec(robot, obj, physics), get_placement("tabletop/07"), obj,
reset.pick_y_offset)`, then put the stage top at `placement.support_height` in tabletop scenes and jitter the
`ROOM_BODY` mocap per reset (and `TABLE_BODY`, with a per-episode table height).
"""

from mobilemani_rl.assets.scenes.compose import (
    HIDDEN_GROUP,
    ROOM_BODY,
    TABLE_BODY,
    RoomJitterCfg,
    add_scene,
    sample_room_offsets,
)
from mobilemani_rl.assets.scenes.placements import (
    PLACEMENTS,
    Placement,
    get_placement,
    placements_for,
    scene_ids,
    setting_of,
)

__all__ = [
    "HIDDEN_GROUP",
    "PLACEMENTS",
    "ROOM_BODY",
    "TABLE_BODY",
    "Placement",
    "RoomJitterCfg",
    "add_scene",
    "get_placement",
    "placements_for",
    "sample_room_offsets",
    "scene_ids",
    "setting_of",
]

"""The 100 scene placements: 5 settings x (16 train + 4 test), deterministic from (setting, index).

Scene ids are `<setting>/<index:02d>`; indices 00–15 are train, 16–19 test (as in the reference, each place
type has 16 train + 4 test room entries; `room_id` indexes within the split).
"""

from __future__ import annotations

import zlib
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from mobilemani_rl.assets.objects import ObjectModel, Place
from mobilemani_rl.assets.scenes.styles import INDOOR_STYLES, PARKING_LOT
from mobilemani_rl.utils.errors import UnknownNameError

TRAIN_PER_SETTING, TEST_PER_SETTING = 16, 4
SUPPORT_HEIGHT_RANGE = (0.22, 0.76)  # tabletop table heights in the reference rooms


@dataclass(frozen=True)
class Placement:
    scene_id: str
    setting: Place
    index: int
    style: str
    seed: int
    support_height: float  # top of the visible table the object stands on (tabletop); 0 elsewhere

    @property
    def split(self) -> str:
        return "train" if self.index < TRAIN_PER_SETTING else "test"

    @property
    def split_index(self) -> int:
        """Position within its split (the reference's `room_id`)."""
        return self.index if self.index < TRAIN_PER_SETTING else self.index - TRAIN_PER_SETTING

    def rng(self) -> np.random.Generator:
        return np.random.default_rng(self.seed)


def _make(setting: Place, index: int) -> Placement:
    scene_id = f"{setting.value}/{index:02d}"
    seed = zlib.crc32(scene_id.encode())
    indoor = tuple(INDOOR_STYLES)
    # Styles rotate with the index (offset per setting) so every split sees several of them.
    style = (
        PARKING_LOT
        if setting is Place.OUTDOOR
        else indoor[(index + list(Place).index(setting)) % len(indoor)]
    )
    height = 0.0
    if setting is Place.TABLETOP:
        height = round(float(np.random.default_rng(seed).uniform(*SUPPORT_HEIGHT_RANGE)), 2)
    return Placement(scene_id, setting, index, style, seed, height)


PLACEMENTS: dict[str, Placement] = {
    p.scene_id: p for p in (_make(s, i) for s in Place for i in range(TRAIN_PER_SETTING + TEST_PER_SETTING))
}


def scene_choices(settings: Iterable[Place]) -> str:
    """The settings' scene ids, one span each (`tabletop/00 to tabletop/19, ...`): a hundred names would bury
    the error."""
    return ", ".join(f"{ids[0]} to {ids[-1]}" for ids in map(scene_ids, settings))


def get_placement(scene_id: str) -> Placement:
    if scene_id not in PLACEMENTS:
        raise UnknownNameError(f"unknown scene {scene_id!r}; valid scenes: {scene_choices(Place)}")
    return PLACEMENTS[scene_id]


def check_setting(obj: ObjectModel, placement: Placement) -> None:
    """The object goes into the placement's setting (a box onto a tabletop, a car into a parking lot)."""
    if setting_of(obj) is not placement.setting:
        raise UnknownNameError(
            f"scene {placement.scene_id!r} is a {placement.setting.value} placement but "
            f"{obj.object_id} ({obj.category}) goes into {setting_of(obj).value}; "
            f"valid scenes: {scene_choices([setting_of(obj)])}"
        )


def setting_of(obj: ObjectModel) -> Place:
    """The placement setting an object goes into (its category's `place`)."""
    return obj.params.place


def scene_ids(setting: Place | str | None = None, split: str | None = None) -> list[str]:
    """Scene ids filtered by setting and/or split, in index order."""
    return [
        sid
        for sid, p in PLACEMENTS.items()
        if (setting is None or p.setting == Place(setting)) and (split is None or p.split == split)
    ]


def placements_for(obj: ObjectModel, split: str | None = None) -> list[Placement]:
    """The placements an object can be put into."""
    return [PLACEMENTS[sid] for sid in scene_ids(setting_of(obj), split)]

"""`python -m mobilemani_rl.envs.scene_sheet --out sheet.png`: head and wrist views, all scenes.

Each placement shows one catalog object of its setting (categories in turn), posed at an episode start of the
object's first skill. A command above the env (it builds one per scene), so not in the asset layer.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # this command renders offscreen; mujoco reads it when imported

import argparse
from collections.abc import Sequence

import numpy as np
from PIL import Image, ImageDraw

from mobilemani_rl.assets.objects import OBJECTS, ObjectModel
from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.assets.scenes.placements import PLACEMENTS, Placement, setting_of
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.render import CameraRenderCfg, CameraRenderer
from mobilemani_rl.utils.cli import count, entry_point, png_path

PER_ROW = 5  # placements per row
LABEL_HEIGHT = 14


def showcase_object(placement: Placement) -> ObjectModel:
    """An object for a placement: its setting's categories in turn, then that category's objects in turn."""
    by_category: dict[str, list[ObjectModel]] = {}
    for obj in OBJECTS.values():
        if setting_of(obj) is placement.setting and not obj.object_id.startswith("test/"):
            by_category.setdefault(obj.category, []).append(obj)
    categories = sorted(by_category)
    objects = by_category[categories[placement.index % len(categories)]]
    return objects[(placement.index // len(categories)) % len(objects)]


def render_placement(placement: Placement, obj: ObjectModel, robot: str, size: int) -> np.ndarray:
    """(size + label, 2 * size, 3): head view | wrist view, labelled."""
    task = TaskCfg(robot=robot, object=obj.object_id, skill=obj.skills[0], scene=placement.scene_id)
    env = MobileManiEnv(EnvCfg(num_envs=1, seed=placement.index, task=task))
    env.reset()
    with CameraRenderer(env.model, CameraRenderCfg(width=size, height=size)) as renderer:
        frames = renderer.render(env.batch.get_data(0))
    tile = Image.new("RGB", (2 * size, size + LABEL_HEIGHT), (20, 20, 20))
    tile.paste(Image.fromarray(frames["head_camera"].rgb), (0, LABEL_HEIGHT))
    tile.paste(Image.fromarray(frames["wrist_camera"].rgb), (size, LABEL_HEIGHT))
    label = f"{placement.scene_id} {placement.split} {placement.style} | {obj.object_id}"
    ImageDraw.Draw(tile).text((3, 1), label, fill=(235, 235, 235))
    return np.asarray(tile)


def build_sheet(robot: str, size: int, scene_ids: Sequence[str] | None = None) -> np.ndarray:
    tiles = []
    for scene_id in scene_ids or list(PLACEMENTS):
        placement = PLACEMENTS[scene_id]
        tiles.append(render_placement(placement, showcase_object(placement), robot, size))
    blank = np.zeros_like(tiles[0])
    rows = []
    for start in range(0, len(tiles), PER_ROW):
        row = tiles[start : start + PER_ROW]
        rows.append(np.concatenate(row + [blank] * (PER_ROW - len(row)), axis=1))
    return np.concatenate(rows, axis=0)


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--out", type=png_path, required=True, help="PNG path to write")
    parser.add_argument("--robot", default="g1", choices=sorted(ROBOTS))
    parser.add_argument("--size", type=count, default=160, help="pixels per camera view")
    parser.add_argument("--scenes", nargs="*", help="scene ids (default: all 100)")


def run(args: argparse.Namespace) -> None:
    sheet = build_sheet(args.robot, args.size, args.scenes)
    tmp = args.out.with_name(f"{args.out.name}.tmp.png")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(sheet).save(tmp)
    os.replace(tmp, args.out)  # no half-written sheet left behind
    print(f"wrote {args.out} ({sheet.shape[1]}x{sheet.shape[0]})")


@entry_point
def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m mobilemani_rl.envs.scene_sheet", description=__doc__)
    configure(parser)
    run(parser.parse_args(argv))


if __name__ == "__main__":
    main()

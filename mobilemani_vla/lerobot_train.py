"""`lerobot-train` on a MobileManiDataset, with the project's quiet video libraries (one line saying PyAV
decodes instead of lerobot's ~60-line torchcodec traceback on every dataset open, mobilemani_data.video) and
the camera frames read from the frame cache instead of decoded per sample (mobilemani_vla.lerobot_frames).
LeRobot's arguments, plus `--frame_cache=false` to decode as stock LeRobot does:

    python -m mobilemani_vla.lerobot_train --policy.type=act --dataset.root=<dataset> ... \\
        [--frame_cache=false]
"""

from __future__ import annotations

import argparse
import sys
from contextlib import nullcontext

from mobilemani_data.metadata import open_dataset_metadata
from mobilemani_data.video import quiet_video_libraries
from mobilemani_rl.cli import entry_point
from mobilemani_rl.registry import InputError, check_values

FLAG = "--frame_cache="
COUNTS = ("steps", "batch_size")


def frame_cache_flag(argv: list[str]) -> tuple[bool, list[str]]:
    """(whether to read frames from the cache, the arguments left for lerobot-train)."""
    values = [arg.removeprefix(FLAG) for arg in argv if arg.startswith(FLAG)]
    if any(v not in ("true", "false") for v in values):
        raise InputError(f"{FLAG}{values[-1]}: give {FLAG}true (the default) or {FLAG}false")
    return (values[-1] if values else "true") == "true", [arg for arg in argv if not arg.startswith(FLAG)]


def check_arguments(argv: list[str]) -> None:
    """The counts LeRobot takes unchecked (`--steps=0` trains nothing, saves nothing and exits 0;
    `--batch_size=0` ends in torch's DataLoader once the dataset is loaded), and the local dataset
    `--dataset.root=` names, with every file it lists: LeRobot would fall back to the hub for a missing one
    and fail offline, naming none."""
    parser = argparse.ArgumentParser(add_help=False, allow_abbrev=False)  # `--key=value` or `--key value`
    parser.add_argument("--dataset.root", dest="root")
    parser.add_argument("--dataset.repo_id", dest="repo_id", default="local/dataset")
    for count in COUNTS:
        parser.add_argument(f"--{count}")
    given, _ = parser.parse_known_args(argv)
    check_values(
        (f"--{count}", value, value.isdigit() and int(value) >= 1, "a whole number of at least 1")
        for count in COUNTS
        if (value := getattr(given, count)) is not None
    )
    if given.root is not None:
        open_dataset_metadata(given.repo_id, given.root)


@entry_point
def main() -> None:
    use_cache, sys.argv[1:] = frame_cache_flag(sys.argv[1:])
    quiet_video_libraries()
    check_arguments(sys.argv[1:])
    # Imported after the log filter is in place: lerobot warns about torchcodec while importing.
    from lerobot.scripts.lerobot_train import main as lerobot_train

    from mobilemani_vla.lerobot_frames import served_from_frame_cache

    with served_from_frame_cache() if use_cache else nullcontext():
        lerobot_train()


if __name__ == "__main__":
    main()

"""`lerobot-train` on a MobileManiDataset, with the project's quiet video libraries (one line saying PyAV
decodes instead of lerobot's ~60-line torchcodec traceback on every dataset open,
mobilemani_rl.utils.video_logs) and the camera frames read from the frame cache instead of decoded per sample
(mobilemani_vla.data.lerobot_frames).
LeRobot's arguments, plus `--frame_cache=false` to decode as stock LeRobot does and `--preset=cpu` for the
project's settings of the policy type (mobilemani_vla.lerobot_presets; flags given replace the preset's):

    python -m mobilemani_vla.lerobot_train --policy.type=act --dataset.root=<dataset> --output_dir=<run> \\
        ... [--frame_cache=false] [--preset=cpu]

Rerunning the same command continues, as our own stages do (lerobot-train refuses an existing --output_dir,
and its `--resume=true` trains to the steps the run was first given): from the run's last checkpoint to
--steps, nothing when it has them; fewer steps, or another policy type, dataset or batch size, are refused
by name. A finished run records its dataset's digest in `<output_dir>/dataset.json`, as our own checkpoints
do, for the tables' captions.
"""

from __future__ import annotations

import argparse
import shutil
import sys
from contextlib import nullcontext
from pathlib import Path

from mobilemani_data.metadata import open_dataset_metadata
from mobilemani_rl.utils.cli import entry_point
from mobilemani_rl.utils.errors import ConfigMismatchError, InputError, OutputExistsError, check_values
from mobilemani_rl.utils.io import read_json, write_json_atomic
from mobilemani_rl.utils.video_logs import quiet_video_libraries
from mobilemani_vla.checkpoint import DATASET
from mobilemani_vla.data.dataset import dataset_digest
from mobilemani_vla.lerobot_presets import ensure_smolvlm_backbone, merge_flags, preset_flags

FLAG = "--frame_cache="
PRESET = "--preset="
COUNTS = ("steps", "batch_size")
LAST = Path("checkpoints", "last")  # lerobot-train's link to a run's newest checkpoint


def frame_cache_flag(argv: list[str]) -> tuple[bool, list[str]]:
    """(whether to read frames from the cache, the arguments left for lerobot-train)."""
    values = [arg.removeprefix(FLAG) for arg in argv if arg.startswith(FLAG)]
    if any(v not in ("true", "false") for v in values):
        raise InputError(f"{FLAG}{values[-1]}: give {FLAG}true (the default) or {FLAG}false")
    return (values[-1] if values else "true") == "true", [arg for arg in argv if not arg.startswith(FLAG)]


def with_preset(argv: list[str]) -> list[str]:
    """The arguments without `--preset=`, after the preset's flags for the keys they do not give."""
    presets = [arg.removeprefix(PRESET) for arg in argv if arg.startswith(PRESET)]
    rest = [arg for arg in argv if not arg.startswith(PRESET)]
    return merge_flags(preset_flags(presets[-1], given(rest).policy_type), rest) if presets else rest


def given(argv: list[str]) -> argparse.Namespace:
    """The arguments this wrapper reads, in either of LeRobot's forms (`--key=value`, `--key value`)."""
    parser = argparse.ArgumentParser(add_help=False, allow_abbrev=False)
    for key in ("dataset.root", "policy.type", "output_dir", "resume", *COUNTS):
        parser.add_argument(f"--{key}", dest=key.replace(".", "_"))
    parser.add_argument("--dataset.repo_id", dest="repo_id", default="local/dataset")
    return parser.parse_known_args(argv)[0]


def check_arguments(argv: list[str]) -> None:
    """The counts LeRobot takes unchecked (`--steps=0` trains nothing, saves nothing and exits 0;
    `--batch_size=0` ends in torch's DataLoader once the dataset is loaded), and the local dataset
    `--dataset.root=` names, with every file it lists: LeRobot would fall back to the hub for a missing one
    and fail offline, naming none."""
    args = given(argv)
    check_values(
        (f"--{count}", value, value.isdigit() and int(value) >= 1, "a whole number of at least 1")
        for count in COUNTS
        if (value := getattr(args, count)) is not None
    )
    if args.dataset_root is not None:
        open_dataset_metadata(args.repo_id, args.dataset_root)


def trained_step(run: Path) -> int:
    """The step of the run's newest finished checkpoint (0 where it has none)."""
    step_file = run / LAST / "training_state" / "training_step.json"
    return read_json(step_file)["step"] if step_file.exists() else 0


def keep_last_checkpoint(run: Path) -> None:
    """Deletes every checkpoint but the one `last` links to (lerobot-train keeps them all, each with its
    optimizer state)."""
    if not (run / LAST).exists():
        return
    newest = (run / LAST).resolve()
    for checkpoint in (run / "checkpoints").iterdir():
        if checkpoint.name != LAST.name and checkpoint.resolve() != newest:
            shutil.rmtree(checkpoint)


def continued(argv: list[str]) -> list[str] | None:
    """lerobot-train's arguments for what --output_dir holds: as given for a new run; a resume to --steps from
    the last checkpoint; None when the run has its --steps already."""
    args = given(argv)
    if args.output_dir is None or args.resume is not None or not Path(args.output_dir).exists():
        return argv
    run = Path(args.output_dir)
    if not (reached := trained_step(run)):
        saved_one = any(run.glob("checkpoints/*/training_state/training_step.json"))
        if not saved_one and {p.name for p in run.iterdir()} <= {"checkpoints"}:  # killed in its first save
            print(f"{run} holds no finished checkpoint: starting it again", flush=True)
            shutil.rmtree(run)
            return argv
        raise OutputExistsError(
            f"--output_dir={run} exists without a LeRobot run's {LAST} to resume from; "
            "choose another or delete it"
        )
    saved = read_json(run / LAST / "pretrained_model" / "train_config.json")
    changed = changed_settings(saved, args)
    steps = int(args.steps) if args.steps is not None else saved["steps"]
    if steps < reached:
        changed.append(f"--steps: {reached} trained, {steps} asked (only --steps may grow)")
    if changed:
        raise ConfigMismatchError(
            f"{run} was trained with other settings ({'; '.join(changed)}); choose another --output_dir "
            "(LEROBOT_OUT) or delete it to start over"
        )
    if steps == reached:
        print(f"{run}: trained {reached} steps already", flush=True)
        return None
    print(f"{run}: resuming from step {reached} to {steps}", flush=True)
    return [
        "--resume=true",
        f"--config_path={run / LAST / 'pretrained_model' / 'train_config.json'}",
        f"--steps={steps}",
    ]


def changed_settings(saved: dict, args: argparse.Namespace) -> list[str]:
    """The settings given that differ from those the run was trained with."""
    root = args.dataset_root and Path(args.dataset_root).resolve()
    batch_size = args.batch_size and int(args.batch_size)
    return [
        f"--{key}: {old} -> {new}"
        for key, old, new in (
            ("policy.type", saved["policy"]["type"], args.policy_type),
            ("dataset.root", Path(saved["dataset"]["root"]).resolve(), root),
            ("batch_size", saved["batch_size"], batch_size),
        )
        if new is not None and new != old
    ]


@entry_point
def main() -> None:
    use_cache, arguments = frame_cache_flag(sys.argv[1:])
    sys.argv[1:] = with_preset(arguments)
    quiet_video_libraries()
    check_arguments(sys.argv[1:])
    output_dir = given(sys.argv[1:]).output_dir  # a resume's arguments name its config instead
    if (arguments := continued(sys.argv[1:])) is None:
        return
    sys.argv[1:] = arguments
    ensure_smolvlm_backbone(arguments)
    # Imported after the log filter is in place: lerobot warns about torchcodec while importing.
    from lerobot.scripts.lerobot_train import main as lerobot_train

    from mobilemani_vla.data.lerobot_frames import served_from_frame_cache

    with served_from_frame_cache() if use_cache else nullcontext():
        lerobot_train()
    if output_dir is not None:
        record_dataset(Path(output_dir))


def record_dataset(run: Path) -> None:
    """`<run>/dataset.json`: the root and digest of the dataset the run's config names."""
    dataset = read_json(run / LAST / "pretrained_model" / "train_config.json")["dataset"]
    record = {"root": dataset["root"], "sha256": dataset_digest(dataset["repo_id"], dataset["root"])}
    write_json_atomic(run / DATASET, record)  # a stopped write leaves no half record for the tables to read


if __name__ == "__main__":
    main()

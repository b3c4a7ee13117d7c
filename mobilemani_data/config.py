"""Dataset configuration dataclasses: DataRootCfg is conf/data.yaml's schema, its groups (conf/data/subset,
conf/data/teacher) change the defaults of SubsetCfg and TeacherCfg.

The env block (conf/env) is the RL env's EnvCfg; collection turns on its recording resets
(docs/reference.md, "Rooms"). A composed config converts with
`to_dataclass(with_env_task(cfg), DataCfg).check()`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import get_args

import av

from mobilemani_data import schema
from mobilemani_rl.envs.base_frame import Convention
from mobilemani_rl.envs.config import EnvCfg, EnvParamsCfg, RobotChoiceCfg, check_env_block
from mobilemani_rl.envs.tasks import SubsetCfg
from mobilemani_rl.utils.config_store import register_schema
from mobilemani_rl.utils.errors import (
    InputError,
    check_choice,
    check_positive,
    check_values,
    first_sentence,
    is_count,
)


@dataclass
class TeacherCfg:
    kind: str = "scripted"  # scripted | ppo
    runs_dir: str = (
        "outputs/rl"  # ppo: newest <runs_dir>/<robot>/<object or else its category>/<skill>/model_*.pt
    )
    min_train_success: float = 0.1  # ppo: skip tasks whose teacher trained below this, as the reference does


@dataclass
class CollectCfg:
    num_envs: int = 16  # episodes run in parallel per combination
    max_steps: int = 6000  # control steps of the batch per combination before giving up, as in the reference
    seed: int = 0  # mixed with each combination's name into its env seed
    compression: int = 4  # gzip level of the HDF5 datasets
    action_noise: float = 0.0  # std of Gaussian noise added to the executed (not the recorded) action: DART
    # Combinations collected side by side in worker processes (mobilemani_rl.utils.process_pool); the
    # episodes do not depend on it, so a rerun may change it.
    workers: int = 1


@dataclass
class ShardCfg:
    """This job's share of the combinations (Hydra multirun: shard.index=0,1,2,3 shard.count=4)."""

    index: int = 0
    count: int = 1


@dataclass
class ExportCfg:
    repo_id: str = "mobilemani/g1"
    width: int = 520  # the reference's camera size
    height: int = 520
    vcodec: str = "libsvtav1"
    crf: int = 30
    gop: int = 2  # keyframe interval: small so random frame access stays cheap
    preset: int | None = None  # None: the codec's default
    streaming_encoding: bool = True  # encode frames as they come (no temporary PNGs)
    action_convention: str = "conjugate"  # base_frame.Convention; "reference": the released data's quirk
    # The image streams written, i.e. what a stock LeRobot policy trains on
    # (it takes every observation.images.*):
    cameras: list[str] = field(default_factory=lambda: ["head", "wrist"])  # any of schema.CAMERAS
    modalities: list[str] = field(default_factory=lambda: ["rgb", "depth", "seg"])  # any of schema.MODALITIES
    # Each episode's room repainted (colours blended toward random ones by up to this much, lights scaled;
    # robot and object untouched: mobilemani_rl/render/appearance.py), so a policy sees more than the train
    # rooms' colours. 0: the rooms as built (the paper's data); `make recipe` and `make demo` use 0.6.
    room_repaint: float = 0.0
    # PPO teachers' action labels averaged over this many control steps (odd; 1: as recorded): their motion
    # stays, their fast reactions to inputs a VLA never observes go (mobilemani_data.convert.smoothed_labels).
    # The scripted teacher's labels are smooth already and stay raw.
    ppo_label_window: int = 9
    # At most this many episodes of each combination, the first ones of its shard: those a collection of that
    # many would have kept (episodes are kept in a fixed rank order, mobilemani_data.recorder). None: all.
    episodes_per_combination: int | None = None
    # Worker processes rendering parts of the dataset side by side (mobilemani_rl.utils.process_pool); the
    # dataset does not depend on it, so a resumed export may change it.
    workers: int = 1
    # Consecutive combinations of the subset per part: the unit a worker renders and an interrupted export
    # keeps (mobilemani_data.parts).
    combinations_per_part: int = 16
    overwrite: bool = False

    def check(self) -> None:
        """Streams non-empty, known and without repeats, room_repaint in [0, 1], vcodec an encoder that opens
        at the export's size with these options: checked with the rest of DataCfg, so `make data` stops before
        collecting, not after."""
        for key, values, valid in (
            ("export.cameras", self.cameras, schema.CAMERAS),
            ("export.modalities", self.modalities, schema.MODALITIES),
        ):
            if not values or any(v not in valid for v in values) or len(set(values)) != len(values):
                raise InputError(
                    f"invalid {key} {list(values)}: name one or more of {list(valid)}, without repeats"
                )
        if not 0.0 <= self.room_repaint <= 1.0:
            raise InputError(
                f"export.room_repaint={self.room_repaint} must lie in [0, 1] (0: rooms as built)"
            )
        window = self.ppo_label_window
        if not (is_count(window) and window % 2 == 1):
            raise InputError(
                f"export.ppo_label_window={window!r} must be an odd whole number of control steps "
                "(1: the labels as recorded)"
            )
        try:
            av.Codec(self.vcodec, "w")
        except av.codec.codec.UnknownCodecError as err:  # only PyAV knows this ffmpeg's encoders
            raise InputError(
                f"export.vcodec={self.vcodec!r} is no video encoder of this ffmpeg; "
                "e.g. libsvtav1 (the default) or h264"
            ) from err
        # Opening the encoder with the export's size and options is ffmpeg's own check: libx264 refuses an odd
        # size in 4:2:0 and SVT-AV1 a preset out of range only when the first frame comes, after collection.
        context = av.CodecContext.create(self.vcodec, "w")
        # yuv420p: the pixel format of LeRobot's RGB encoder, which the export uses
        context.width, context.height, context.pix_fmt = self.width, self.height, "yuv420p"
        context.time_base = Fraction(1, schema.FPS)
        options = {"g": self.gop, "crf": self.crf} | ({} if self.preset is None else {"preset": self.preset})
        context.options = {key: str(value) for key, value in options.items()}
        level = av.logging.get_level()
        if level is None:  # PyAV ignores ffmpeg's log by default; its error then quotes no line of it
            av.logging.set_level(av.logging.ERROR)
        try:
            with av.logging.Capture():  # ffmpeg's own lines would precede the one error; it quotes the last
                context.open()
        except av.error.FFmpegError as err:
            given = ", ".join(
                f"export.{key}={getattr(self, key)}" for key in ("width", "height", "crf", "gop", "preset")
            )
            odd = self.width % 2 or self.height % 2
            raise InputError(
                f"export.vcodec={self.vcodec} does not open with {given}: {first_sentence(err)}"
                + (" (4:2:0 video such as h264's needs even sizes)" if odd else "")
            ) from err
        finally:
            av.logging.set_level(level)


@dataclass
class ValidateCfg:
    replay_episodes: int = 2  # episodes whose states are replayed and compared
    tolerance: float = 1e-6
    decode_frames: int = 4  # frames decoded through LeRobotDataset per check


@dataclass
class PreviewCfg:
    episodes: int = 3
    path: str = "outputs/data/g1/preview.mp4"


@dataclass
class BenchCfg:
    sizes: list[int] = field(default_factory=lambda: [224, 520])
    episodes: int = 2
    out: str = "outputs/data/g1/bench.json"


@dataclass
class DataCfg:
    robot: str = "g1"
    data_dir: str = "outputs/data/g1"
    raw_dir: str = "outputs/data/g1/raw"
    dataset_dir: str = "outputs/data/g1/lerobot"
    subset: SubsetCfg = field(default_factory=SubsetCfg)
    teacher: TeacherCfg = field(default_factory=TeacherCfg)
    collect: CollectCfg = field(default_factory=CollectCfg)
    shard: ShardCfg = field(default_factory=ShardCfg)
    export: ExportCfg = field(default_factory=ExportCfg)
    validate: ValidateCfg = field(default_factory=ValidateCfg)
    preview: PreviewCfg = field(default_factory=PreviewCfg)
    bench: BenchCfg = field(default_factory=BenchCfg)
    env: EnvCfg = field(default_factory=EnvCfg)

    def check(self) -> DataCfg:
        """Checked before any stage writes: a zero or negative count would record empty shards marked
        complete, and a misspelt action convention would export the other one."""
        check_positive(
            {
                "subset.episodes": self.subset.episodes,
                "subset.scenes_per_object": self.subset.scenes_per_object,
                "subset.objects_per_category": self.subset.objects_per_category,
                "collect.num_envs": self.collect.num_envs,
                "collect.max_steps": self.collect.max_steps,
                "collect.workers": self.collect.workers,
                "shard.count": self.shard.count,
                "export.width": self.export.width,
                "export.height": self.export.height,
                "export.gop": self.export.gop,
                "export.episodes_per_combination": self.export.episodes_per_combination,
                "export.workers": self.export.workers,
                "export.combinations_per_part": self.export.combinations_per_part,
                "preview.episodes": self.preview.episodes,
                "bench.episodes": self.bench.episodes,
            }
        )
        noise, level = self.collect.action_noise, self.collect.compression
        threshold, crf = self.teacher.min_train_success, self.export.crf
        checks, sizes = self.validate, self.bench.sizes
        check_values(
            [
                # a negative count would slice from the end: every shard but the last ones
                ("validate.replay_episodes", checks.replay_episodes, checks.replay_episodes >= 0, ">= 0"),
                ("validate.decode_frames", checks.decode_frames, checks.decode_frames >= 0, ">= 0"),
                ("validate.tolerance", checks.tolerance, checks.tolerance >= 0, ">= 0"),
                ("bench.sizes", sizes, bool(sizes) and min(sizes) >= 1, "image sizes in pixels, >= 1"),
                ("collect.action_noise", noise, noise >= 0, "a standard deviation, >= 0"),
                ("collect.compression", level, 0 <= level <= 9, "a gzip level, 0 to 9"),
                ("teacher.min_train_success", threshold, 0 <= threshold <= 1, "a success rate, 0 to 1"),
                ("export.crf", crf, 0 <= crf <= 63, "0 to 63, the widest range of our encoders"),
            ]
        )
        check_choice(self.export.action_convention, get_args(Convention), "export.action_convention")
        self.export.check()
        check_env_block(self.env, {"num_envs": "collect.num_envs", "seed": "collect.seed"})
        return self


@dataclass
class DataRootCfg(DataCfg):
    """conf/data.yaml's schema: the env block without its task, which the robot group's block makes."""

    env: EnvParamsCfg = field(default_factory=EnvParamsCfg)
    task: RobotChoiceCfg = field(default_factory=RobotChoiceCfg)


register_schema("data_schema", DataRootCfg)

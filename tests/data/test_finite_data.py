"""Non-finite values never reach a dataset or a model: validate names every NaN or infinity of the shards and
of the exported parquet files (shard or file, episode, key, first row), export leaves such an episode out with
a warning and a count, and VLA training refuses such frames before it starts, naming the file."""

import shutil
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq
import pytest
from data_helpers import tiny_cfg

from mobilemani_data.collect import collect
from mobilemani_data.export import export
from mobilemani_data.metadata import read_episodes, read_export_report
from mobilemani_data.shards import read_shard, shard_paths, write_shard
from mobilemani_data.validate import validate
from mobilemani_rl.utils.errors import InputError
from mobilemani_rl.utils.io import non_finite

# One combination (one object, skill and scene), two episodes; no replay: the finite check does not need it.
SUBSET = [
    "subset.objects=[dishwasher/0000]",
    "subset.skills=[open]",
    "subset.scenes_per_object=1",
    "validate.replay_episodes=0",
]


def test_non_finite_names_each_float_array_with_its_first_bad_row():
    rows = np.zeros((6, 3), np.float32)
    rows[4, 2], rows[5, 0] = np.inf, np.nan
    flat = np.array([0.0, np.nan, np.nan])
    found = non_finite(
        {"rows": rows, "flat": flat, "flags": np.array([True, False]), "fine": np.ones((2, 2))}
    )
    assert found == [("rows", 4, np.inf), ("flat", 1, pytest.approx(np.nan, nan_ok=True))]
    assert non_finite({"fine": np.zeros((3, 2)), "ints": np.arange(3)}) == []


@pytest.fixture(scope="module")
def collected(tmp_path_factory) -> Path:
    """The raw shard of one tiny combination, collected once; each test works on its own copy."""
    data_dir = tmp_path_factory.mktemp("finite")
    collect(tiny_cfg(data_dir, *SUBSET))
    return data_dir


def copy_of(collected: Path, tmp_path: Path):
    shutil.copytree(collected, tmp_path, dirs_exist_ok=True)
    cfg = tiny_cfg(tmp_path, *SUBSET)
    (path,) = shard_paths(Path(cfg.raw_dir), "g1")
    return cfg, path


def poison_shard(path: Path, episode: int, key: str, row: int, value: float) -> None:
    """Rewrite the shard with one value of one array replaced, as a faulty teacher or simulator would record
    it (the shard stays complete and readable)."""
    shard = read_shard(path)
    values = shard.episodes[episode].arrays[key].copy()
    values[row, ...] = value
    shard.episodes[episode].arrays[key] = values
    write_shard(path, shard.header, shard.episodes)


@pytest.mark.parametrize(
    ("key", "row", "value"), [("action", 5, np.nan), ("state", 3, np.inf), ("goal_pos", 1, np.nan)]
)
def test_validate_names_the_shard_episode_key_and_row_of_a_non_finite_value(
    collected, tmp_path, key, row, value
):
    cfg, path = copy_of(collected, tmp_path)
    assert validate(cfg) == []
    poison_shard(path, 1, key, row, value)
    assert validate(cfg) == [f"{path}: episode 1 {key} row {row} is not finite ({value})"]


def test_export_leaves_a_non_finite_episode_out_with_a_warning_and_a_count(collected, tmp_path, capsys):
    cfg, path = copy_of(collected, tmp_path)
    poison_shard(path, 1, "action", 5, np.nan)
    message = f"{path}: episode 1 action row 5 is not finite (nan)"
    report = export(cfg)
    assert (report.episodes, report.skipped_episodes, report.skipped) == (1, [message], [])
    assert f"skipped episode {message}" in capsys.readouterr().err
    root = Path(cfg.dataset_dir)
    assert [line["shard_episode"] for line in read_episodes(root)] == [0]
    assert read_export_report(root)["skipped_episodes"] == [message]
    assert export(cfg).skipped_episodes == [message]  # a rerun reuses the dataset and still reports it
    # Only the raw shard is at fault: the dataset holds finite numbers alone.
    assert validate(cfg) == [message]


def poison_parquet(path: Path, key: str, episode: int, frame: int, value: float) -> None:
    """Replace the first component of `key` at (episode, frame) in a LeRobot data file, keeping its schema."""
    table = pq.read_table(path)
    episodes, frames = table["episode_index"].to_numpy(), table["frame_index"].to_numpy()
    (row,) = np.flatnonzero((episodes == episode) & (frames == frame))
    column = table[key].combine_chunks()
    values = pc.list_flatten(column).to_numpy(zero_copy_only=False).reshape(len(column), -1).copy()
    values[row, 0] = value
    index = table.schema.get_field_index(key)
    table = table.set_column(index, table.schema.field(key), pa.array(values.tolist(), type=column.type))
    pq.write_table(table, path)


def test_validate_names_the_file_episode_key_and_frame_of_a_non_finite_dataset_value(collected, tmp_path):
    cfg, _ = copy_of(collected, tmp_path)
    assert export(cfg).episodes == 2 and validate(cfg) == []
    (data_file,) = sorted((Path(cfg.dataset_dir) / "data").rglob("*.parquet"))
    poison_parquet(data_file, "observation.state", 1, 4, np.inf)
    assert validate(cfg) == [f"{data_file}: episode 1 observation.state frame 4 is not finite (inf)"]


# ------------------------------------------------------------------------------------------- VLA training


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory) -> Path:
    from mobilemani_vla.data.synthetic import write_synthetic_dataset

    return write_synthetic_dataset(tmp_path_factory.mktemp("vla") / "g1", episodes=2, length=6)


def vla_cfg(root: Path, out: Path):
    from mobilemani_vla.config import compose_vla_cfg

    overrides = ["vla/model=tiny", "vla/train=cpu", f"data.root={root}", "data.repo_id=synthetic/g1"]
    overrides += ["data.heldout_episodes=0", f"train.output_dir={out}", "train.logger=none", "train.steps=1"]
    return compose_vla_cfg([*overrides, "train.progress=false", "train.batch_size=2"])


@pytest.mark.parametrize(("key", "value"), [("action", np.nan), ("observation.state", -np.inf)])
def test_vla_training_refuses_non_finite_frames_before_it_starts(synthetic, tmp_path, key, value):
    from mobilemani_vla.data.dataset import open_data
    from mobilemani_vla.train import train

    root = tmp_path / "g1"
    shutil.copytree(synthetic, root)
    (data_file,) = sorted((root / "data").rglob("*.parquet"))
    poison_parquet(data_file, key, 1, 2, value)
    message = f"{data_file}: episode 1 {key} frame 2 is not finite \\({value}\\); training refuses"
    cfg = vla_cfg(root, tmp_path / "run")
    with pytest.raises(InputError, match=message):
        open_data(cfg, 32, progress=False)
    with pytest.raises(InputError, match=message):
        train(cfg)
    assert not (tmp_path / "run").exists() and not (root / "vla_cache").exists()


def test_vla_normalisation_statistics_refuse_non_finite_values(synthetic):
    from mobilemani_vla.data.dataset import FrameTable, fit_normalizer, open_metadata, vector_keys

    cfg = vla_cfg(synthetic, Path("unused"))
    table = FrameTable.read(open_metadata(cfg), vector_keys(cfg.inputs.states))
    fit_normalizer(table, np.arange(len(table.episode_index)), cfg.inputs.states)
    table.columns["action"] = table.columns["action"].copy()
    table.columns["action"][3, 1] = np.nan
    with pytest.raises(InputError, match=r"action of frame 3 is not finite \(nan\)"):
        fit_normalizer(table, np.arange(len(table.episode_index)), cfg.inputs.states)

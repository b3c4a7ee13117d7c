"""The export takes the subset's combinations from the raw shards, caps the episodes per combination, renders
its parts on worker processes, and resumes an interrupted run from the parts it finished."""

import itertools
import json
import shutil
from collections.abc import Callable
from pathlib import Path

import pytest
from data_helpers import tiny_cfg
from lerobot.datasets.lerobot_dataset import LeRobotDataset

from mobilemani_data import export as export_module
from mobilemani_data.collect import collect
from mobilemani_data.combos import shard_path
from mobilemani_data.export import export, export_source
from mobilemani_data.metadata import read_episodes, read_export_report
from mobilemani_data.parts import MANIFEST, PARTIAL, finished_manifest, parts_dir
from mobilemani_data.shards import read_shard, shard_paths
from mobilemani_data.stats import dataset_action_roughness, dataset_stats
from mobilemani_data.validate import validate
from mobilemani_rl.envs.tasks import select_combinations
from mobilemani_rl.utils.errors import MissingFileError

# One object, both skills, both scenes, two episodes each: four shards. Exported small: head RGB at 32 px.
SUBSET = ["subset.objects=[dishwasher/0000]", "subset.episodes=2"]
SMALL = ["export.width=32", "export.height=32", "export.cameras=[head]", "export.modalities=[rgb]"]


@pytest.fixture(scope="module")
def collected(tmp_path_factory) -> Path:
    """The four raw shards, collected once; each test exports from its own copy."""
    data_dir = tmp_path_factory.mktemp("parts")
    collect(tiny_cfg(data_dir, *SUBSET))
    return data_dir


def copy_of(collected: Path, tmp_path: Path, *overrides: str):
    shutil.copytree(collected, tmp_path, dirs_exist_ok=True)
    return tiny_cfg(tmp_path, *SUBSET, *SMALL, *overrides)


def collected_shards(cfg) -> list[str]:
    """The subset's shards that exist, in the subset's order (relative to raw_dir)."""
    names = [str(shard_path(combo)) for combo in select_combinations(cfg.robot, cfg.subset)]
    return [name for name in names if (Path(cfg.raw_dir) / name).is_file()]


class Stopped(Exception):
    """Stands for whatever ends an export midway: Ctrl-C, a kill, a full disk."""


def test_the_subsets_combinations_are_exported_capped_by_workers_and_validate(collected, tmp_path, capsys):
    """Of four shards, the subset (open, three scenes) names two and a third combination never collected; each
    keeps its first episode. Two workers render one part per combination."""
    cfg = copy_of(
        collected,
        tmp_path,
        "subset.skills=[open]",
        "subset.scenes_per_object=3",
        "export.episodes_per_combination=1",
        "export.combinations_per_part=1",
        "export.workers=2",
    )
    report = export(cfg)
    assert (report.episodes, report.missing, report.skipped) == (2, 1, [])
    out = capsys.readouterr().out
    assert "2 shards in 2 parts, 2 to render" in out and "| 2/2 parts, " in out
    root = Path(cfg.dataset_dir)
    lines = read_episodes(root)
    first, second = collected_shards(cfg)
    assert [(line["episode_index"], line["shard"], line["shard_episode"]) for line in lines] == [
        (0, first, 0),
        (1, second, 0),
    ]
    assert read_export_report(root)["episodes_per_combination"] == 1
    assert not parts_dir(root).exists() and not root.with_name(root.name + PARTIAL).exists()
    dataset = LeRobotDataset(cfg.export.repo_id, root=root, video_backend="pyav")
    assert dataset.num_episodes == 2 and len(dataset) == report.frames == sum(
        line["length"] for line in lines
    )
    assert validate(cfg) == []
    table = dataset_stats(lines)
    assert table["total"]["all"]["episodes"] == 2 and set(table["skill"]) == {"open"}
    assert len(dataset_action_roughness(root, cfg.export.repo_id)) == 7


def test_a_subset_without_shards_stops_before_anything_is_written(collected, tmp_path):
    cfg = copy_of(collected, tmp_path, "subset.objects=[cart/0000]")
    with pytest.raises(MissingFileError, match=r"none of the subset's 4 combinations has a shard under "):
        export(cfg)
    root = Path(cfg.dataset_dir)
    assert not root.exists() and not parts_dir(root).exists()


def test_a_combination_without_a_success_is_named_and_the_rest_exported(collected, tmp_path):
    """A teacher can fail every attempt in a combination (its shard holds no episode): export names that
    shard in its report, apart from damaged ones, exports the others, and validate passes."""
    cfg = copy_of(collected, tmp_path)
    failed = Path(cfg.raw_dir) / collected_shards(cfg)[1]
    failed.unlink()
    recollect = tiny_cfg(tmp_path, *SUBSET, "collect.max_steps=1")  # one control step: no episode can succeed
    collect(recollect)
    assert read_shard(failed).episodes == []
    report = export(cfg)
    assert report.skipped == [] and report.empty == [
        f"{failed}: no episode (collection found no success within its attempts)"
    ]
    assert read_export_report(Path(cfg.dataset_dir))["empty"] == report.empty
    lines = read_episodes(Path(cfg.dataset_dir))
    assert len(lines) == report.episodes == 6 and str(failed.relative_to(cfg.raw_dir)) not in {
        line["shard"] for line in lines
    }
    assert validate(cfg) == []


def interrupted_export(cfg, monkeypatch, stop: Callable[[Path], bool]) -> None:
    """Export with the shard reader raising Stopped at the first shard `stop` names, as a kill would."""
    read_shard = export_module.read_shard

    def reading(path: Path):
        if stop(path):
            raise Stopped
        return read_shard(path)

    monkeypatch.setattr(export_module, "read_shard", reading)
    with pytest.raises(Stopped):
        export(cfg)
    monkeypatch.undo()


def test_an_interrupted_export_keeps_its_finished_parts_and_the_rerun_adds_the_rest(
    collected, tmp_path, monkeypatch, capsys
):
    cfg = copy_of(collected, tmp_path, "export.combinations_per_part=1")
    root, folder = Path(cfg.dataset_dir), parts_dir(Path(cfg.dataset_dir))
    reads = itertools.count(1)
    interrupted_export(cfg, monkeypatch, lambda _: next(reads) == 3)  # stopped at the third shard
    # Two parts complete, the third cut short under its temporary name, no dataset.
    assert sorted(p.name for p in folder.iterdir()) == ["part-00000", "part-00001", "part-00002.partial"]
    assert not root.exists() and not root.with_name(root.name + PARTIAL).exists()

    capsys.readouterr()
    report = export(cfg)
    assert "4 shards in 4 parts, 2 finished before, 2 to render" in capsys.readouterr().out
    lines = read_episodes(root)
    shards = collected_shards(cfg)
    assert [(line["shard"], line["shard_episode"]) for line in lines] == [
        (s, k) for s in shards for k in (0, 1)
    ]
    assert [line["episode_index"] for line in lines] == list(range(8))
    # Only the last two parts were rendered again; the dataset holds every episode once.
    assert report.rendered_frames == sum(line["length"] for line in lines[4:]) < report.frames
    assert validate(cfg) == [] and not folder.exists()


def test_parts_of_an_interrupted_export_with_other_settings_are_rendered_again(
    collected, tmp_path, monkeypatch
):
    cfg = copy_of(collected, tmp_path, "export.combinations_per_part=1")
    first = Path(cfg.raw_dir) / collected_shards(cfg)[0]
    interrupted_export(cfg, monkeypatch, lambda path: path != first)  # stopped at the second shard
    folder = parts_dir(Path(cfg.dataset_dir))
    assert (folder / "part-00000" / MANIFEST).is_file()
    cfg.export.combinations_per_part = 4  # one part: part-00000 again, now of four shards
    report = export(cfg)
    assert report.episodes == 8 and report.rendered_frames == report.frames and validate(cfg) == []


def test_a_part_is_reused_only_for_the_same_shards_and_settings(collected, tmp_path):
    cfg = copy_of(collected, tmp_path)
    raw = Path(cfg.raw_dir)
    paths = shard_paths(raw, "g1")[:2]
    source = export_source(cfg.export, raw, paths)
    part = tmp_path / "part-00000"
    part.mkdir()
    (part / MANIFEST).write_text(json.dumps({"source": source, "lines": []}))
    assert finished_manifest(part, source) is not None
    cfg.export.crf = 10
    assert finished_manifest(part, export_source(cfg.export, raw, paths)) is None
    assert finished_manifest(part, export_source(cfg.export, raw, paths[:1])) is None

"""Evaluation results: one JSON record per episode in a JSONL file, resumable, and their summaries.

A record's key is (robot, object_id, skill, scene, episode); a rerun skips keys already present and appends
the rest. A line cut off by a killed run is dropped before appending, so the file never holds a broken record.
Success rates follow the reference's metric (`load_vla_test_success`): per object first, then the mean
(and std) over objects, for each skill, category, (category, skill group) and overall.
"""

from __future__ import annotations

import json
import os
from collections import defaultdict
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from mobilemani_rl.utils.io import read_json
from mobilemani_rl.utils.stats import wilson_interval
from mobilemani_rl.utils.writer_lock import WriterLock, busy

Key = tuple[str, str, str, str, int]
# The paper's per-category table groups skills by their motion: grasp-and-move vs. push-to-close.
SKILL_GROUPS = {
    "open": "open/pull/pick",
    "pull": "open/pull/pick",
    "pick": "open/pull/pick",
    "close": "close/push",
    "push": "close/push",
}


def record_key(record: dict) -> Key:
    return (record["robot"], record["object_id"], record["skill"], record["scene"], int(record["episode"]))


def read_records(path: Path) -> list[dict]:
    if not path.exists():
        return []
    records = []
    for line in path.read_text().splitlines():
        try:
            records.append(json.loads(line))
        except json.JSONDecodeError:
            continue  # the cut-off last line of a killed run; `ResultsFile` drops it before appending
    return records


def summary_path(results_path: Path) -> Path:
    """Where an evaluation writes its results file's summary: last, once every episode of the run is in."""
    return results_path.with_name(f"{results_path.stem}.summary.json")


def finished(results_path: Path, records: list[dict]) -> bool:
    """Whether the evaluation that wrote these records ran to its end. A running, killed or later grown run
    has no summary, or one of fewer episodes."""
    path = summary_path(results_path)
    return path.exists() and read_json(path).get("episodes") == len(records)


class ResultsFile:
    """The results file of one run, held by one writer at a time: two evaluations under one name would append
    the same episodes twice."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._lock = WriterLock(path.with_name(path.name + ".lock"), busy("evaluation", path, "name"))
        self._drop_partial_line()
        self.done = {record_key(r) for r in read_records(path)}

    def __enter__(self) -> ResultsFile:
        return self

    def __exit__(self, *exc: object) -> None:
        self._lock.release()

    def _drop_partial_line(self) -> None:
        if not self.path.exists():
            return
        data = self.path.read_bytes()
        if data and not data.endswith(b"\n"):
            tmp = self.path.with_name(self.path.name + ".tmp")
            tmp.write_bytes(data[: data.rfind(b"\n") + 1])
            os.replace(tmp, self.path)

    def append(self, records: Iterable[dict]) -> int:
        """Append records whose key is new; returns how many were written."""
        new = [r for r in records if record_key(r) not in self.done]
        if new:
            with self.path.open("a") as f:
                f.write("".join(json.dumps(r, sort_keys=True) + "\n" for r in new))
                f.flush()
                os.fsync(f.fileno())
            self.done.update(record_key(r) for r in new)
        return len(new)


def _over_objects(records: list[dict]) -> dict:
    per_object: dict[str, list[bool]] = defaultdict(list)
    for r in records:
        per_object[r["object_id"]].append(bool(r["success"]))
    rates = np.array([np.mean(v) for v in per_object.values()])
    successes = sum(sum(v) for v in per_object.values())
    return {
        "success_rate": float(rates.mean()),
        "std_over_objects": float(rates.std()),
        "objects": len(rates),
        "episodes": len(records),
        "successes": int(successes),
        # over the pooled episodes (the success rate itself averages objects, equal when their counts are)
        "ci95": list(wilson_interval(int(successes), len(records))),
    }


def _grouped(records: list[dict], key) -> dict[str, dict]:
    groups: dict[str, list[dict]] = defaultdict(list)
    for r in records:
        groups[key(r)].append(r)
    return {name: _over_objects(group) for name, group in sorted(groups.items())}


def summarize(records: list[dict]) -> dict:
    if not records:
        return {"episodes": 0}
    return {
        "overall": _over_objects(records),
        "per_skill": _grouped(records, lambda r: r["skill"]),
        "per_category": _grouped(records, lambda r: r["category"]),
        "per_category_skill_group": _grouped(
            records, lambda r: f"{r['category']}|{SKILL_GROUPS[r['skill']]}"
        ),
        "episodes": len(records),
        # NaN action entries the policy produced (the env applies them as 0, as the reference does)
        "nan_action_entries": sum(r.get("nan_actions", 0) for r in records),
    }

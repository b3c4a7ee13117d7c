"""Object catalog: counts and splits, determinism, bad input, the task table and the CLI."""

from __future__ import annotations

import subprocess
import sys
from collections import Counter

import pytest

from mobilemani_rl.assets.objects import CATALOG, SPLITS, catalog_ids, check_skill, get_object, task_table
from mobilemani_rl.assets.objects.catalog import make_object
from mobilemani_rl.utils.errors import UnknownNameError

EXPECTED = {  # train + test per category (docs/reference.md, "Per-category constants")
    "box": (10, 4),
    "toilet": (25, 5),
    "laptop": (30, 6),
    "trashcan": (30, 7),
    "dishwasher": (20, 5),
    "oven": (10, 2),
    "microwave": (3, 2),
    "refrigerator": (40, 12),
    "washing_machine": (10, 2),
    "car": (10, 2),
    "safe": (15, 4),
    "fridge": (8, 2),
    "cabinet": (20, 2),
    "window": (15, 3),
    "lever_door": (18, 4),
    "round_door": (20, 5),
    "faucet": (60, 18),
    "table": (90, 18),
    "cart": (12, 4),
    "holistic": (60, 18),
}


def test_counts_per_category_and_split():
    counts = Counter((obj.category, obj.split) for obj in CATALOG.values())
    assert {c: (counts[c, "train"], counts[c, "test"]) for c in EXPECTED} == EXPECTED
    assert len(CATALOG) == 631 and len(EXPECTED) == 20


def test_split_layout_follows_the_reference_lists():
    assert catalog_ids("box", "train") == [f"box/{i:04d}" for i in range(10)]
    assert catalog_ids("box", "test") == [f"box/{i:04d}" for i in range(10, 14)]
    assert catalog_ids("holistic", "test") == [f"holistic/{i:04d}" for i in range(18)]
    assert catalog_ids("table", "test")[0] == "table/0090"


def test_all_objects_compile_with_the_interface_the_env_reads():
    for oid, obj in CATALOG.items():
        model = obj.build_spec().compile()
        assert (
            model.body(1).name == "object" and model.site("grasp").bodyid[0] == model.body(obj.grasp_body).id
        )
        if obj.joint is not None:
            assert model.njnt == 1 and model.jnt_limited[0], oid
            kin = obj.kinematics
            assert kin.init_value < kin.open_value <= kin.joint_range[1], oid


def test_ids_are_deterministic():
    for oid in ("box/0003", "faucet/0042", "holistic/0007", "cart/0011", "refrigerator/0050"):
        category, index = oid.split("/")
        assert make_object(category, int(index)).build_spec().to_xml() == CATALOG[oid].build_spec().to_xml()


def test_unknown_names_raise_one_clear_error():
    # one span per category, not the catalogue's hundreds of ids
    with pytest.raises(UnknownNameError, match="valid objects: box/0000 to box/0013, toilet/.*test/can$"):
        get_object("box/9999")
    with pytest.raises(UnknownNameError, match="valid categories: .*washing_machine"):
        catalog_ids("washer")
    with pytest.raises(UnknownNameError, match="valid splits: test, train"):
        catalog_ids(split="val")
    with pytest.raises(UnknownNameError, match="valid skills for it: pull, push"):
        check_skill(get_object("cart/0000"), "open")


def test_task_table_has_every_valid_combination():
    tasks = task_table()
    per_robot = 2 * (631 - 16 - 78) + 2 * 16 + 78
    assert len(tasks) == 2 * per_robot == len(set(tasks))
    skills = {(t.object_id.split("/")[0], t.skill) for t in tasks}
    assert ("cart", "pull") in skills and ("holistic", "pick") in skills and ("oven", "close") in skills
    assert ("holistic", "open") not in skills and ("cart", "close") not in skills
    assert len(task_table(("g1",), category="box", split="test")) == 4 * 2
    with pytest.raises(UnknownNameError, match="valid robots"):
        task_table(("r2d2",))


def test_cli_list_prints_counts():
    out = subprocess.run(
        [sys.executable, "-m", "mobilemani_rl.assets", "list"], capture_output=True, text=True, check=True
    ).stdout
    assert "washing_machine" in out and out.splitlines()[-1].split() == ["all", "506", "125", "631"]
    assert SPLITS == ("train", "test")


@pytest.mark.slow
def test_cli_preview_writes_a_contact_sheet(tmp_path):
    out = tmp_path / "sheet.png"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "mobilemani_rl.assets",
            "preview",
            "--out",
            str(out),
            "--per-category",
            "1",
            "--size",
            "64",
        ],
        check=True,
        capture_output=True,
    )
    assert out.stat().st_size > 10_000

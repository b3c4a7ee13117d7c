"""The base-mobility table (the paper's Table 8) from the teacher sweep's row records."""

import json

import pytest

from mobilemani_rl.rl import base_mobility


def write_rows(path, rows: dict[tuple[str, str], dict[str, float]], episodes: int = 64):
    records = [
        {
            "category": category,
            "skill": skill,
            "test_object_success": rates,
            "test_objects": len(rates),
            "episodes_per_object": episodes,
        }
        for (category, skill), rates in rows.items()
    ]
    path.write_text(json.dumps(records))
    return path


def test_rows_count_their_test_episodes_and_the_mean_averages_the_rows(tmp_path, capsys):
    mobile = write_rows(
        tmp_path / "mobile.json",
        {("laptop", "open"): {"laptop/a": 1.0, "laptop/b": 0.5}, ("cart", "pull"): {"cart/a": 0.75}},
    )
    fixed = write_rows(tmp_path / "fixed.json", {("laptop", "open"): {"laptop/a": 0.25, "laptop/b": 0.0}})
    out = tmp_path / "tables"
    base_mobility.main(["--mobile", str(mobile), "--fixed", str(fixed), "--out", str(out)])
    table = (out / "rl_base_mobility.md").read_text()
    assert table == capsys.readouterr().out.rstrip("\n") + "\n"
    rows = {line.split(" | ")[0].lstrip("| "): line for line in table.splitlines() if line.startswith("| ")}
    # laptop: 96 of 128 mobile, 16 of 128 fixed; cart pull only mobile
    assert rows["laptop open"] == "| laptop open | 75.0 (128; 66.8-81.7) | 12.5 (128; 7.8-19.3) |"
    assert rows["cart pull"].endswith("| 75.0 (64; 63.2-84.0) | - |")
    assert rows["cabinet open"] == "| cabinet open | - | - |"
    # the means cover the rows both columns have: laptop open alone
    mean = "| Mean (rows in both) | 75.0 (1 row; 67.5-82.5) | 12.5 (1 row; 6.8-18.2) |"
    assert rows["Mean (rows in both)"] == mean
    assert rows["Paper (G1)"] == "| Paper (G1) | 82.8 | 25.4 |"
    assert r"\begin{tabular}" in (out / "rl_base_mobility.tex").read_text()


def test_a_missing_file_is_named_and_the_paper_column_still_prints(tmp_path, capsys):
    mobile = write_rows(tmp_path / "mobile.json", {("laptop", "open"): {"laptop/a": 1.0}})
    base_mobility.main(["--mobile", str(mobile), "--fixed", str(tmp_path / "absent.json")])
    out = capsys.readouterr().out
    assert out.startswith(f"missing input: no teacher rows in {tmp_path / 'absent.json'}")
    assert "| Paper (G1) | 82.8 | 25.4 |" in out


@pytest.mark.parametrize(("successes", "episodes"), [(0, 256), (256, 256), (130, 256)])
def test_the_mean_interval_stays_inside_0_and_100(successes, episodes):
    assert base_mobility.mean_cell([(96, 128), (48, 64)]).startswith("75.0 (2 rows; ")  # the rows' rates
    cell = base_mobility.mean_cell([(successes, episodes)])
    low, high = (float(x) for x in cell.split("; ")[1].rstrip(")").split("-"))
    assert 0.0 <= low <= 100 * successes / episodes <= high <= 100.0

"""The collect line's whole-train-set time from sampled collect logs (docs/results/collect_train_set.md):

    python docs/results/collect_train_set/estimate.py collect_sample.log collect_pick.log > estimate.json

Each collected combination's log line ends with its seconds; a row's mean over its sampled combinations times
the row's combinations in the train set is its time, and rows not sampled (all articulated) get the sampled
articulated rows' lowest and highest mean, which bound the estimate.
"""

import collections
import json
import re
import statistics
import sys

from mobilemani_rl.tasks import SubsetCfg, select_combinations

LINE = re.compile(
    r"\] g1/(\w+)/\d+/(\w+)/\S+: (\d+)/(\d+) episodes from (\d+) attempts"
    r".*?, mean length (\d+) \(([\d.]+) s\)"
)


def main(paths: list[str]) -> dict:
    sampled = collections.defaultdict(list)
    for path in paths:
        for category, skill, got, wanted, attempts, length, seconds in LINE.findall(open(path).read()):
            combination = {"seconds": float(seconds), "attempts": int(attempts), "length": int(length)}
            sampled[f"{category} {skill}"].append({**combination, "all": got == wanted})
    train_set = select_combinations("g1", SubsetCfg())
    in_train_set = collections.Counter(f"{c.category} {c.skill}" for c in train_set)
    rows = {
        row: {
            "combinations_sampled": len(found),
            "seconds_mean": round(statistics.mean(c["seconds"] for c in found), 3),
            "seconds_min_max": [min(c["seconds"] for c in found), max(c["seconds"] for c in found)],
            "attempts_mean": round(statistics.mean(c["attempts"] for c in found), 1),
            "length_mean": round(statistics.mean(c["length"] for c in found)),
            "all_episodes_found": all(c["all"] for c in found),
            "combinations_in_train_set": in_train_set[row],
        }
        for row, found in sampled.items()
    }
    articulated = [r["seconds_mean"] for name, r in rows.items() if name.split()[1] in ("open", "close")]
    measured = sum(r["seconds_mean"] * r["combinations_in_train_set"] for r in rows.values())
    unsampled = sum(n for row, n in in_train_set.items() if row not in rows)
    bounds = (min(articulated), max(articulated))
    return {
        "rows": rows,
        "combinations_in_train_set": sum(in_train_set.values()),
        "combinations_in_sampled_rows": sum(r["combinations_in_train_set"] for r in rows.values()),
        "sampled_rows_hours": round(measured / 3600, 2),
        "unsampled_combinations": unsampled,
        "whole_set_hours": [round((measured + unsampled * seconds) / 3600, 2) for seconds in bounds],
    }


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1:]), indent=1))

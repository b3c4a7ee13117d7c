"""The rate of one run of the collect line (a piece, when it is stopped and rerun) from its log and shards:

    python docs/results/collect_train_set/piece_rate.py collect_piece1.log <data_dir>/raw > piece1.json

Elapsed seconds come from the log's last progress line, env steps from the headers of the shards its lines
name (batch control steps x the env's num_envs); per row, the mean of each combination's own seconds (with
workers, several run at once, so these add up to more than the elapsed time).
"""

import collections
import json
import re
import statistics
import sys
from pathlib import Path

from estimate import LINE
from omegaconf import OmegaConf

from mobilemani_data.combos import shard_path
from mobilemani_data.shards import complete_header
from mobilemani_rl.tasks import SubsetCfg, select_combinations

NAME = re.compile(r"^\[\d+/\d+\] (\S+): \d+/\d+ episodes", re.M)
PROGRESS = re.compile(r"\| (\d+)/(\d+) combinations, (?:(\d+)h)?(?:(\d+)m)?(?:(\d+)s)? elapsed")


def main(log_path: str, raw_dir: str) -> dict:
    log = open(log_path).read()
    done, todo, hours, minutes, seconds = PROGRESS.findall(log)[-1]
    elapsed = 3600 * int(hours or 0) + 60 * int(minutes or 0) + int(seconds or 0)
    by_name = {c.name: c for c in select_combinations("g1", SubsetCfg())}
    collected = NAME.findall(log)
    env_steps = 0
    for name in collected:
        header = complete_header(Path(raw_dir) / shard_path(by_name[name]))
        env_steps += header["steps"] * OmegaConf.create(header["env_cfg"]).num_envs
    rows = collections.defaultdict(list)
    for category, skill, *_, combination_seconds in LINE.findall(log):
        rows[f"{category} {skill}"].append(float(combination_seconds))
    return {
        "combinations_done": int(done),
        "combinations_to_collect": int(todo),
        # left out at once, without episodes: its teacher trained below teacher.min_train_success
        "combinations_skipped": int(done) - len(collected),
        "elapsed_seconds": elapsed,
        "combinations_per_minute": round(60 * len(collected) / elapsed, 1),
        "env_steps": env_steps,
        "env_steps_per_second": round(env_steps / elapsed),
        "rows": {
            row: {"combinations": len(s), "seconds_mean": round(statistics.mean(s), 3)}
            for row, s in rows.items()
        },
    }


if __name__ == "__main__":
    print(json.dumps(main(*sys.argv[1:]), indent=1))

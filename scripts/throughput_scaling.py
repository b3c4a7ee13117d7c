"""How the env's and PPO's throughput grow with the number of envs, beside the raw MuJoCo limit of the same
run: env control steps/s (`mobilemani_rl.envs.bench`) and PPO samples/s with the `cpu` preset
(`mobilemani_rl.rl.bench`, `rl.ppo.num_envs` set per row) for one robot, as JSON, a Markdown table and a plot.

    python -m scripts.throughput_scaling [--robot g1] [--envs 64 256 1024] [--seconds 6] [--iterations 5] \
        [--out docs/results/throughput/scaling]

Writes <out>.json, <out>.md and <out>.png.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from matplotlib.figure import Figure  # the object API: no pyplot backend to select, nothing global changed

from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.envs.bench import bench_task
from mobilemani_rl.rl.bench import bench_preset
from mobilemani_rl.utils.cli import count, entry_point, seconds
from mobilemani_rl.utils.io import write_json_atomic
from mobilemani_rl.utils.table_format import Table


def cpu_model() -> str:
    """The CPU as lscpu names it, with its family and model numbers (which tell e.g. Zen 4 from Zen 5)."""
    info: dict[str, str] = {}
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        key, _, value = line.partition(":")
        info.setdefault(key.strip(), value.strip())
        if not line.strip():
            break
    return f"{info.get('model name', 'unknown')} (family {info.get('cpu family')}, model {info.get('model')})"


def measure(robot: str, envs: list[int], budget: float, iterations: int) -> list[dict]:
    rows = []
    for n in envs:
        env = bench_task(robot, n, budget)
        ppo = bench_preset("cpu", robot, iterations, f"rl.ppo.num_envs={n}")
        rows.append(
            {
                "num_envs": n,
                "env_steps_per_s": env["env_steps_per_s"],
                "env_raw_steps_per_s": env["raw_steps_per_s"],
                "env_over_raw": env["env_over_raw"],
                "ppo_samples_per_s": ppo["samples_per_s"],
                "ppo_raw_steps_per_s": ppo["raw_env_steps_per_s"],
                "ppo_over_raw": ppo["ppo_over_raw"],
                "ppo_precision": ppo["precision"],
            }
        )
    return rows


def markdown(robot: str, rows: list[dict]) -> str:
    header = [f"{robot} envs", "env steps/s", "raw steps/s", "env/raw", "PPO samples/s", "raw steps/s"]
    cells = [
        [
            str(r["num_envs"]),
            f"{r['env_steps_per_s']:,}",
            f"{r['env_raw_steps_per_s']:,}",
            f"{r['env_over_raw']:.2f}",
            f"{r['ppo_samples_per_s']:,}",
            f"{r['ppo_raw_steps_per_s']:,}",
            f"{r['ppo_over_raw']:.3f}",
            r["ppo_precision"],
        ]
        for r in rows
    ]
    return Table([*header, "PPO/raw", "PPO precision"], cells).markdown()


def plot(robot: str, rows: list[dict], path: Path) -> None:
    envs = [r["num_envs"] for r in rows]
    fig = Figure(figsize=(9, 3.4))
    rates, ratios = fig.subplots(1, 2)
    rates.plot(envs, [r["env_raw_steps_per_s"] for r in rows], "k--o", label="raw MuJoCo")
    rates.plot(envs, [r["env_steps_per_s"] for r in rows], "-o", label="env")
    rates.plot(envs, [r["ppo_samples_per_s"] for r in rows], "-o", label="PPO (cpu preset)")
    rates.set(ylim=(0, None), ylabel="steps or samples / s", title=f"{robot}: throughput")
    rates.legend(loc="upper center", bbox_to_anchor=(0.5, 0.9))
    ratios.plot(envs, [r["env_over_raw"] for r in rows], "-o", label="env / raw")
    ratios.plot(envs, [r["ppo_over_raw"] for r in rows], "-o", label="PPO / raw")
    ratios.set(ylim=(0, 1), title="share of the raw limit")
    ratios.legend()
    for axes in (rates, ratios):
        axes.set_xscale("log", base=2)
        axes.minorticks_off()
        axes.set_xticks(envs, [str(n) for n in envs])
        axes.set_xlabel("envs")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


@entry_point
def main(argv: list[str] | None = None) -> list[dict]:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--robot", default="g1", choices=sorted(ROBOTS))
    parser.add_argument("--envs", nargs="+", type=count, default=[64, 256, 1024])
    parser.add_argument("--seconds", type=seconds, default=6.0, help="env timing budget per env count")
    parser.add_argument("--iterations", type=count, default=5, help="PPO iterations timed per env count")
    parser.add_argument("--out", type=Path, default=Path("outputs/throughput_scaling"))
    args = parser.parse_args(argv)
    rows = measure(args.robot, args.envs, args.seconds, args.iterations)
    table = markdown(args.robot, rows)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    record = {"robot": args.robot, "cpu": cpu_model(), "rows": rows}
    write_json_atomic(args.out.with_suffix(".json"), record)
    args.out.with_suffix(".md").write_text(table)
    plot(args.robot, rows, args.out.with_suffix(".png"))
    print(table + json.dumps(record, indent=2))
    return rows


if __name__ == "__main__":
    main()

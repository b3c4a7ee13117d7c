"""Every benchmark in one run: simulation, rendering, PPO training, dataset export, VLA training/inference.

    python scripts/bench_all.py [--quick] [--out outputs/bench.json]

Each benchmark runs as its own process (its own CLI), so one can be rerun alone; this script collects their
JSON into one file and prints one table of the headline figures next to the raw limit measured in the same run
(raw `mujoco.batch.Batch` stepping for simulation and PPO, raw `mujoco.Renderer` calls for rendering).
`--quick` shortens every measurement (for a smoke run; the figures are then noisier).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path


def _json_objects(text: str) -> list[dict]:
    decoder = json.JSONDecoder()
    found = []
    for start in [i for i, ch in enumerate(text) if ch == "{" and (i == 0 or text[i - 1] == "\n")]:
        try:
            value, _ = decoder.raw_decode(text, start)
        except json.JSONDecodeError:
            continue
        if isinstance(value, dict):
            found.append(value)
    return found


def run(module: str, args: list[str], json_file: Path | None = None) -> dict:
    """Run `python -m module args`; return the JSON it wrote to json_file, else the largest it printed."""
    print(f"$ python -m {module} {' '.join(args)}", flush=True)
    done = subprocess.run([sys.executable, "-m", module, *args], capture_output=True, text=True, check=True)
    if json_file is not None:
        return json.loads(json_file.read_text())
    return max(_json_objects(done.stdout), key=lambda d: len(json.dumps(d)))


# Per benchmark: the headline's name and one result's (case, figure, raw limit, ratio).
HEADLINES: tuple[tuple[str, str, Callable[[dict], tuple[str, str, str, str]]], ...] = (
    (
        "sim",
        "sim env steps/s",
        lambda r: (
            f"{r['robot']} x{r['num_envs']}",
            str(r["env_steps_per_s"]),
            str(r["raw_steps_per_s"]),
            f"{r['env_over_raw']:.2f}",
        ),
    ),
    (
        "render",
        "render frames/s (2 cam x RGB+D+S)",
        lambda r: (
            f"{r['size']}px",
            f"{r['frames_per_s']:.1f}",
            f"{r['raw_rgb_renders_per_s']:.1f}",
            f"{r['ratio_frame_vs_raw']:.2f}",
        ),
    ),
    (
        "ppo",
        "PPO samples/s",
        lambda r: (
            f"{r['preset']} {r['robot']}",
            str(r["samples_per_s"]),
            str(r["raw_env_steps_per_s"]),
            f"{r['ppo_over_raw']:.3f}",
        ),
    ),
    (
        "export",
        "export frames/s (render+encode)",
        lambda r: (
            f"{r['size']}px, {r['episode_mb']} MB/episode",
            f"{r['frames_per_s']:.1f}",
            "-",
            f"render share {r['render_share']:.2f}",
        ),
    ),
)


def headline_rows(report: dict) -> list[tuple[str, str, str, str, str]]:
    """(benchmark, case, figure, raw limit, ratio) rows."""
    rows = [(name, *cells(r)) for key, name, cells in HEADLINES for r in report[key]["results"]]
    for r in report["vla"]["cpu"]:
        rows.append(("VLA train samples/s", r["model"], f"{r['train_samples_per_s']:.2f}", "-", "-"))
        rows.append(("VLA s per chunk (10 DDIM)", r["model"], f"{r['infer_s_per_chunk']:.3f}", "-", "-"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", type=Path, default=Path("outputs/bench.json"))
    args = parser.parse_args()
    quick = args.quick
    with tempfile.TemporaryDirectory() as tmp:
        export_json = Path(tmp) / "export.json"
        report = {
            "sim": run(
                "mobilemani_rl.envs.bench",
                ["--seconds", "2" if quick else "6"] + (["--envs", "64", "256"] if quick else []),
            ),
            "render": run("mobilemani_rl.envs.render_bench", ["--seconds", "1" if quick else "5"]),
            "ppo": run(
                "mobilemani_rl.rl.bench",
                ["--iterations", "1" if quick else "3"] + (["--presets", "cpu"] if quick else []),
            ),
            "export": run(
                "mobilemani_data.bench",
                [f"bench.out={export_json}"] + (["bench.sizes=[224]", "bench.episodes=1"] if quick else []),
                export_json,
            ),
            "vla": run("mobilemani_vla.bench", ["--steps", "1", "--runs", "1"] if quick else []),
        }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=2))
    rows = [("benchmark", "case", "figure", "raw limit", "ratio"), *headline_rows(report)]
    widths = [max(len(r[i]) for r in rows) for i in range(5)]
    for row in rows:
        print("  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

"""Write the `make demo` report: what each stage produced, with the tables, plots and a rollout video if
one was recorded.

    python scripts/demo_report.py outputs/demo

Reads the stage outputs under the demo directory (teacher run and its evaluation, the LeRobot dataset, the VLA
training losses, the closed-loop summaries, the tables) and writes <demo>/report.md, printing it too.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from omegaconf import OmegaConf  # noqa: E402

from mobilemani_data.schema import EXPORT_REPORT_FILE  # noqa: E402
from mobilemani_rl.utils.stats import wilson_interval  # noqa: E402
from mobilemani_vla.config import DiffusionCfg  # noqa: E402
from mobilemani_vla.eval.results import read_records  # noqa: E402
from scripts.plot_training_curve import plot_runs  # noqa: E402


def newest(paths: list[Path]) -> Path | None:
    return max(paths, key=lambda p: p.stat().st_mtime) if paths else None


def yaml_value(path: Path, keys: tuple[str, ...]) -> object:
    value = OmegaConf.load(path)
    for key in keys:
        value = value[key]
    return value


def teacher_section(demo: Path, out: Path) -> list[str]:
    run = demo / "rl" / "g1" / "test" / "box" / "open"
    evaluation = newest(list(run.glob("eval_*.json")))
    result = json.loads((run / "result.json").read_text())
    seed = yaml_value(run / "config.yaml", ("rl", "ppo", "seed"))
    lines = [
        "## 1. Teacher (PPO, g1 opens test/box)",
        "",
        f"- PPO seed {seed}: {result['iterations']} iterations, {result['samples'] / 1e6:.2f} M samples",
    ]
    if evaluation is not None:
        rate = json.loads(evaluation.read_text())["success_rate"]
        lines.append(
            f"- success over 256 seeded evaluation episodes: **{100 * rate:.1f}%** ({evaluation.name})"
        )
    curve = plot_runs([run], out / "teacher_curve.png")
    return lines + ["", f"![teacher training curve]({curve.name})", ""]


def dataset_section(demo: Path) -> list[str]:
    meta = demo / "data" / "lerobot" / "meta"
    info = json.loads((meta / "info.json").read_text())
    episodes, frames = info["total_episodes"], info["total_frames"]
    rows = [json.loads(line) for line in (meta / "mobilemani_episodes.jsonl").read_text().splitlines()]
    rooms = len({row["scene"] for row in rows})
    report = json.loads((demo / "data" / "lerobot" / EXPORT_REPORT_FILE).read_text())
    window = report["source"]["ppo_label_window"]
    return [
        f"## 2. Dataset (LeRobot v3, teacher rollouts in {rooms} train rooms)",
        "",
        f"- {episodes} successful episodes, {frames} frames ({frames / max(episodes, 1):.0f} per episode at "
        f"{info['fps']} FPS), cameras: "
        f"{', '.join(k for k in info['features'] if k.startswith('observation.images'))}",
        f"- action labels: the teacher's clean actions averaged over {window} control steps "
        "(`export.ppo_label_window`); the envs executed them with DART noise",
        "",
    ]


DIAGNOSTIC_ROWS = (
    ("image", "real images, instruction and state"),
    ("null_image", "image feature replaced by the null vector"),
    ("null_instruction", "empty instruction"),
    ("wrong_instruction", "wrong instruction"),
    ("no_state", "no state"),
)


def vla_section(demo: Path, out: Path) -> list[str]:
    losses = np.array(json.loads((demo / "vla" / "last_run.json").read_text())["losses"])
    window = max(1, len(losses) // 20)
    smooth = np.convolve(losses, np.ones(window) / window, mode="valid")
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(losses, alpha=0.3, label="per step")
    ax.plot(np.arange(len(smooth)) + window - 1, smooth, label=f"mean of {window}")
    ax.set(xlabel="step", ylabel="diffusion loss (epsilon MSE)", yscale="log")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "vla_loss.png", dpi=120)
    plt.close(fig)
    start, end = losses[: max(1, window)].mean(), losses[-window:].mean()
    lines = [
        "## 3. MobileManiVLA (cpu recipe, CPU)",
        "",
        f"- {len(losses)} training steps; loss {start:.3f} -> {end:.3f}",
        *inputs_lines(demo),
    ]
    diagnostics = demo / "vla" / "diagnostics.jsonl"
    if diagnostics.is_file():
        last = json.loads(diagnostics.read_text().splitlines()[-1])
        lines += [
            "",
            f"Held-out noise-prediction error at step {last['step']} (lower is better; each input "
            "replaced in turn, the rest as trained):",
            "",
            "| input | noise error | minus the real inputs' |",
            "|---|---:|---:|",
        ]
        real = last["noise_mse/image"]
        for key, name in DIAGNOSTIC_ROWS:
            if f"noise_mse/{key}" in last:
                value = last[f"noise_mse/{key}"]
                lines.append(f"| {name} | {value:.4f} | {value - real:+.4f} |")
        lines += open_loop_lines(last)
    return lines + ["", "![VLA loss](vla_loss.png)", ""]


def open_loop_errors(diagnostics: dict) -> tuple[float, float, float] | None:
    """The sampled chunk's held-out error with the images, at the guidance scale the VLA acts with by default,
    and from the null vector alone, if logged: the noise error barely depends on the condition (a denoiser
    tells noise from a smooth chunk without it), this does. -> (scale, with images, null vector)"""
    scale = DiffusionCfg.cfg_scale
    guided = f"open_loop_mse/cfg_{scale:g}"
    if guided not in diagnostics or "open_loop_mse/null_image" not in diagnostics:
        return None
    return scale, diagnostics[guided], diagnostics["open_loop_mse/null_image"]


def open_loop_lines(diagnostics: dict) -> list[str]:
    errors = open_loop_errors(diagnostics)
    if errors is None:
        return []
    scale, with_images, without = errors
    return [
        "",
        f"Held-out open-loop error of the sampled action chunk: {with_images:.3f} with the images "
        f"(guidance {scale:g}), {without:.3f} from the null vector alone ({without - with_images:+.3f}).",
    ]


def inputs_lines(demo: Path) -> list[str]:
    """What the trained VLA reads, from its newest checkpoint's config."""
    config = newest(list((demo / "vla" / "checkpoints").glob("step_*/config.yaml")))
    if config is None:
        return []
    inputs = OmegaConf.load(config).inputs
    lines = [f"- inputs: cameras {', '.join(inputs.cameras)}; states {', '.join(inputs.states) or 'none'}"]
    if "grasp_point" not in inputs.states:
        return lines
    noise = inputs.get("grasp_point_noise", 0.0)  # validated: > 0 only with grasp_point among the states
    lines.append(
        f"- the grasp point it is given is off by N(0, ({100 * noise:g} cm)^2) on each axis: per training "
        "sample, and one offset per evaluation episode"
        if noise > 0
        else "- the grasp point it is given is exact (the paper's pseudo-observation)"
    )
    return lines


def rate_cell(records: list[dict]) -> str:
    wins = sum(bool(r["success"]) for r in records)
    low, high = wilson_interval(wins, len(records))
    return (
        f"{100 * wins / len(records):.1f}% ({wins}/{len(records)}; 95% CI {100 * low:.0f}-{100 * high:.0f}%)"
    )


def eval_section(demo: Path) -> list[str]:
    """Teacher and VLA in the unseen test rooms: the protocol's episodes, the VLA's 40 with seed=1, and the
    VLA's 60 together with their interval, overall and per room."""
    runs = {
        name: read_records(path)
        for name in ("teacher", "vla", "vla_seed1")
        if (path := newest(list((demo / "eval" / "g1" / name).glob("*.jsonl")))) is not None
    }
    lines = [
        "## 4. Closed-loop evaluation (test/box open, the 4 unseen test rooms)",
        "",
        "| policy | episodes | success (95% Wilson interval) |",
        "|---|---|---|",
    ]
    labels = {"teacher": "the protocol's seeds", "vla": "the protocol's seeds", "vla_seed1": "seed=1"}
    for name, records in runs.items():
        lines.append(f"| {name} | {labels[name]} | {rate_cell(records)} |")
    vla = runs.get("vla", []) + runs.get("vla_seed1", [])
    if vla:
        lines.append(f"| **VLA, all** | both | **{rate_cell(vla)}** |")
        rooms = sorted({r["scene"] for r in vla})
        lines += [
            "",
            "VLA per room: "
            + ", ".join(
                f"{room} {sum(r['success'] for r in vla if r['scene'] == room)}/"
                f"{sum(r['scene'] == room for r in vla)}"
                for room in rooms
            ),
        ]
    video = newest(list((demo / "eval" / "g1").rglob("*.mp4")))
    if video is not None:
        lines += ["", f"Rollout video (head camera): [{video.relative_to(demo)}]({video.relative_to(demo)})"]
    else:  # the demo records none: on 2 cores a video doubles the evaluation
        lines += ["", 'No rollout video: add `EVAL_ARGS="video_episodes=1"` to `make eval` to record one.']
    return lines + [""]


def tables_section(demo: Path) -> list[str]:
    lines = ["## 5. Tables", ""]
    for path in sorted((demo / "tables").rglob("*.md")):
        lines += [path.read_text(), ""]
    for png in sorted((demo / "tables").rglob("*.png")):
        lines += [f"![{png.stem}]({png.relative_to(demo)})", ""]
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("demo", type=Path)
    args = parser.parse_args()
    demo = args.demo
    lines = ["# MobileManiBench-MuJoCo demo report", ""]
    lines += teacher_section(demo, demo) + dataset_section(demo) + vla_section(demo, demo)
    lines += eval_section(demo) + tables_section(demo)
    report = demo / "report.md"
    report.write_text("\n".join(lines))
    print("\n".join(lines))
    print(f"wrote {report}")


if __name__ == "__main__":
    main()

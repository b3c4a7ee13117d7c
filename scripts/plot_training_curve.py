"""Plot PPO training curves (training success and mean episode reward against samples and wall time).

    python scripts/plot_training_curve.py outputs/rl/g1/test/box/open [more run dirs] --out curve.png

Reads the TensorBoard events every run writes, so it also works for runs that were interrupted.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import yaml  # noqa: E402
from tensorboard.backend.event_processing.event_accumulator import EventAccumulator  # noqa: E402

from mobilemani_rl.rl.run_dir import WARM_START  # noqa: E402

SUCCESS = "/episode/success_flag"
REWARD = "Train/mean_reward"


def load_run(run_dir: Path) -> dict[str, list[tuple[float, float, float]]]:
    """Per tag: (samples, seconds, value) points, merged over every events file of the run."""
    cfg = yaml.safe_load((run_dir / "config.yaml").read_text())
    per_iteration = cfg["rl"]["ppo"]["num_envs"] * cfg["rl"]["ppo"]["num_steps_per_env"]
    series: dict[str, list[tuple[float, float, float]]] = {SUCCESS: [], REWARD: []}
    # Wall time includes a warm start from the scripted policy, which precedes the first logged iteration.
    warm_start = run_dir / WARM_START
    offset = json.loads(warm_start.read_text())["seconds"] if warm_start.exists() else 0.0
    for events in sorted(run_dir.glob("events.out.tfevents.*")):
        acc = EventAccumulator(str(events))
        acc.Reload()
        for tag in series:
            if tag in acc.Tags()["scalars"]:
                scalars = acc.Scalars(tag)
                start = scalars[0].wall_time if scalars else 0.0
                series[tag] += [
                    ((s.step + 1) * per_iteration, s.wall_time - start + offset, s.value) for s in scalars
                ]
    return series


def plot_runs(runs: list[Path], out: Path) -> Path:
    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    for run_dir in runs:
        series = load_run(run_dir)
        label = "/".join(run_dir.parts[-4:])
        samples, seconds, success = zip(*series[SUCCESS], strict=True) if series[SUCCESS] else ((), (), ())
        axes[0].plot([s / 1e6 for s in samples], success, label=label)
        axes[1].plot([t / 60 for t in seconds], success, label=label)
        if series[REWARD]:
            r_samples, _, reward = zip(*series[REWARD], strict=True)
            axes[2].plot([s / 1e6 for s in r_samples], reward, label=label)
    axes[0].set(xlabel="samples (M)", ylabel="training success", ylim=(0, 1.05))
    axes[1].set(xlabel="wall time (min)", ylabel="training success", ylim=(0, 1.05))
    axes[2].set(xlabel="samples (M)", ylabel="mean episode reward")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("runs", nargs="+", type=Path)
    parser.add_argument("--out", type=Path, default=Path("outputs/training_curve.png"))
    args = parser.parse_args()
    print(f"wrote {plot_runs(args.runs, args.out)}")


if __name__ == "__main__":
    main()

"""`python -m mobilemani_rl.envs.render_bench`: camera rendering throughput in a realistic scene.

Per size: frames/s of `CameraRenderer` producing 2 cameras x (RGB + depth + segmentation), and the raw
`mujoco.Renderer` rate (`update_scene` + `render`, RGB only, one camera) on the same model, state, size and
settings (shadows and MSAA off unless asked), timed in alternating slices in the same run. Prints JSON and
a table. A command above the env (it builds one), so outside the render package.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # this command renders offscreen; mujoco reads it when imported

import argparse
import json
import time
from collections.abc import Callable

import mujoco

from mobilemani_rl.assets.robots import ROBOTS
from mobilemani_rl.envs.config import EnvCfg, TaskCfg
from mobilemani_rl.envs.mobilemani_env import MobileManiEnv
from mobilemani_rl.render.config import CameraRenderCfg
from mobilemani_rl.render.renderer import CameraRenderer
from mobilemani_rl.utils.cli import count, entry_point, seconds


def interleaved_rates(calls: list[Callable[[], object]], seconds: float, rounds: int = 10) -> list[float]:
    """Calls per second of each callable, timed in alternating slices so load changes hit all alike."""
    for call in calls:  # warm-up
        call()
    counts, times = [0] * len(calls), [0.0] * len(calls)
    for _ in range(rounds):
        for k, call in enumerate(calls):
            start = time.perf_counter()
            while (elapsed := time.perf_counter() - start) < seconds / rounds:
                call()
                counts[k] += 1
            times[k] += elapsed
    return [c / t for c, t in zip(counts, times, strict=True)]


def bench_size(model: mujoco.MjModel, data: mujoco.MjData, cfg: CameraRenderCfg, seconds: float) -> dict:
    renderer = CameraRenderer(model, cfg)
    raw = mujoco.Renderer(model, cfg.height, cfg.width)  # after CameraRenderer sized the buffer and MSAA
    camera = cfg.cameras[0]

    def raw_rgb() -> None:
        raw.update_scene(data, camera)
        raw.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = cfg.shadows
        raw.render()

    try:
        ours, baseline = interleaved_rates([lambda: renderer.render(data), raw_rgb], seconds)
    finally:
        renderer.close()
        raw.close()
    return {
        "size": cfg.width,
        "frames_per_s": round(ours, 1),  # one frame = every camera's RGB + depth + segmentation
        "camera_images_per_s": round(ours * len(cfg.cameras) * 3, 1),
        "raw_rgb_renders_per_s": round(baseline, 1),
        "ratio_frame_vs_raw": round(ours / baseline, 3),
    }


@entry_point
def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m mobilemani_rl.envs.render_bench", description=__doc__)
    parser.add_argument("--scene", default="tabletop/02")
    parser.add_argument("--object", default="test/box")
    parser.add_argument("--robot", default="g1", choices=sorted(ROBOTS))
    parser.add_argument("--sizes", type=count, nargs="+", default=[224, 520])
    parser.add_argument("--seconds", type=seconds, default=5.0)
    parser.add_argument("--shadows", action="store_true")
    parser.add_argument("--multisampling", action="store_true")
    args = parser.parse_args(argv)
    task = TaskCfg(robot=args.robot, object=args.object, skill="open", scene=args.scene)
    env = MobileManiEnv(EnvCfg(num_envs=1, task=task))
    env.reset()
    data = env.batch.get_data(0)
    results = [
        bench_size(
            env.model,
            data,
            CameraRenderCfg(width=size, height=size, shadows=args.shadows, multisampling=args.multisampling),
            args.seconds,
        )
        for size in args.sizes
    ]
    report = {
        "scene": args.scene,
        "ngeom": env.model.ngeom,
        "cameras": list(CameraRenderCfg().cameras),
        "shadows": args.shadows,
        "multisampling": args.multisampling,
        "results": results,
    }
    print(json.dumps(report, indent=2))
    print(f"{'size':>5} {'frames/s (2 cam x RGB+D+S)':>27} {'raw RGB renders/s':>18} {'ratio':>7}")
    for r in results:
        print(
            f"{r['size']:>5} {r['frames_per_s']:>27} {r['raw_rgb_renders_per_s']:>18} "
            f"{r['ratio_frame_vs_raw']:>7}"
        )


if __name__ == "__main__":
    main()
